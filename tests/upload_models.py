#!/usr/bin/env python3
"""upload_models.py - uploads every OBJ, PLY, STL, glTF and GLB of Debian's assimp-testmodels (outside
invalid/) to a lucentd as a user would: a .gltf that names other files as multipart/form-data with them
(what `lucent meshes upload` and the web page send), anything else as the body. Prints one line per
refusal and a summary; --named-files-only uploads just the glTFs that name files.

Usage: upload_models.py URL [--named-files-only] [--root DIR]"""
import json
import os
import subprocess
import sys
import tempfile
import urllib.parse

MESH_EXTS = ("obj", "ply", "stl", "gltf", "glb")


def named_files(path):
    """The relative files a glTF's buffers and images name (data: URIs excluded)."""
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
    except (ValueError, UnicodeDecodeError):
        return []
    names = []
    for key in ("buffers", "images"):
        for item in doc.get(key, []) if isinstance(doc.get(key), list) else []:
            uri = item.get("uri") if isinstance(item, dict) else None
            if isinstance(uri, str) and not uri.startswith("data:"):
                names.append(urllib.parse.unquote(uri))
    return names


def upload(url, path, siblings, answer):
    args = ["curl", "-s", "-o", answer, "-w", "%{http_code}"]
    if siblings:
        folder = os.path.dirname(path)
        args += ["-F", "mesh=@%s;filename=%s" % (path, os.path.basename(path))]
        for name in siblings:
            on_disk = os.path.normpath(os.path.join(folder, name))
            if os.path.isfile(on_disk):
                args += ["-F", "file=@%s;filename=%s" % (on_disk, name)]
    else:
        args += ["--data-binary", "@" + path]
    return subprocess.run(args + [url + "/v1/meshes"], capture_output=True, text=True).stdout


def main():
    url = sys.argv[1]
    root = sys.argv[sys.argv.index("--root") + 1] if "--root" in sys.argv else "/usr/share/assimp/models"
    only_named = "--named-files-only" in sys.argv
    results = []
    with tempfile.NamedTemporaryFile(suffix=".json") as answer:
        for folder, dirs, files in sorted(os.walk(root)):
            dirs.sort()
            if os.path.relpath(folder, root).split(os.sep)[0] == "invalid":
                continue
            for name in sorted(files):
                if name.rsplit(".", 1)[-1].lower() not in MESH_EXTS:
                    continue
                path = os.path.join(folder, name)
                siblings = named_files(path) if name.lower().endswith(".gltf") else []
                if only_named and not siblings:
                    continue
                code = upload(url, path, siblings, answer.name)
                detail = ""
                if code not in ("200", "201"):
                    try:
                        with open(answer.name) as f:
                            detail = json.load(f).get("detail", "")
                    except ValueError:
                        detail = "(no JSON answer)"
                results.append((os.path.relpath(path, root), bool(siblings), code, detail))
    for rel, sent_with, code, detail in results:
        if code not in ("200", "201"):
            print("refused %s %s%s: %s" % (code, rel, " (with its files)" if sent_with else "", detail[:140]))
    accepted = sum(code in ("200", "201") for _, _, code, _ in results)
    with_files = [r for r in results if r[1]]
    print("accepted %d of %d; %d sent with the files they name, %d of those accepted" %
          (accepted, len(results), len(with_files), sum(r[2] in ("200", "201") for r in with_files)))


if __name__ == "__main__":
    main()
