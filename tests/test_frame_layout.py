#!/usr/bin/env python3
"""test_frame_layout.py - the C mirror of the per-frame uniform block (renderer/core/frame_uniforms.h) against the
block itself (shaders/frame.glsl): every member a shader uses must lie at the offset glslang's reflection
gives it under std140, and the block must have the C struct's size. Both backends upload the C struct as
it is, so a drift would feed a shader the wrong numbers with no error anywhere.

Usage: test_frame_layout.py GLSLANG SHADER_DIR TEST_FRAME_LAYOUT"""
import re
import subprocess
import sys

glslang, shader_dir, printer = sys.argv[1:4]
shaders = ["projection.vert", "projection.frag", "scatter.comp", "ownership.comp"]
c_offsets = {}
for line in subprocess.run([printer], capture_output=True, text=True, check=True).stdout.splitlines():
    name, offset = line.rsplit(" ", 1)
    c_offsets[name] = int(offset)

passed = failed = 0
def check(ok, what):
    global passed, failed
    passed += ok
    failed += not ok
    print(("ok   " if ok else "FAIL ") + what)

seen = {}
for shader in shaders:
    out = subprocess.run([glslang, "-V", "-q", "--target-env", "vulkan1.1", "-o", "/dev/null",
                          "%s/%s" % (shader_dir, shader)], capture_output=True, text=True)
    members = dict((m, int(o)) for m, o in re.findall(r"^Frame\.(\w+): offset (-?\d+)", out.stdout, re.M))
    size = re.search(r"^Frame: offset -1, .*? size (\d+)", out.stdout, re.M)
    if not size:
        check(out.returncode == 0 and not members, "%s: does not use the Frame block" % shader)
        continue
    wrong = ["%s (GLSL %d, C %s)" % (m, o, c_offsets.get(m)) for m, o in sorted(members.items())
             if c_offsets.get(m) != o]
    check(not wrong and int(size.group(1)) == c_offsets["(size)"],
          "%s: %d members used, at the C offsets; block size %s, C struct %d%s" %
          (shader, len(members), size.group(1), c_offsets["(size)"], "; differ: " + ", ".join(wrong) if wrong else ""))
    seen.update(members)
unused = sorted(set(c_offsets) - set(seen) - {"(size)"})
check(not unused, "every C member is used by some shader, so every offset was checked (unchecked: %s)" %
      (", ".join(unused) or "none"))
print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
