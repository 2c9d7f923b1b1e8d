#!/usr/bin/env python3
"""unit_sandbox_check.py - whether what lucentd did (an strace -f log) stays inside a systemd unit's
SystemCallFilter=, RestrictAddressFamilies= and RestrictNamespaces=. systemd cannot run here, so the
unit's filters are applied to a trace of the real daemon instead. Prints each measure; exit 1 on any
call the unit would refuse. Usage: unit_sandbox_check.py UNIT_FILE STRACE_LOG"""
import re
import subprocess
import sys

unit, trace = sys.argv[1], sys.argv[2]


def settings(name):
    values = []
    for line in open(unit):
        line = line.strip()
        if line.startswith(name + "="):
            values.append(line[len(name) + 1:])
    return values


def syscall_groups():
    """Every @group systemd knows, with its members (groups inside groups left as @names)."""
    out = subprocess.run(["systemd-analyze", "syscall-filter"], capture_output=True, text=True, check=True).stdout
    groups, current = {}, None
    for line in out.splitlines():
        if line.startswith("@"):
            current = line.split()[0]
            groups[current] = []
        elif current and line.strip() and not line.strip().startswith("#"):
            groups[current].append(line.strip())
    return groups


def expand(names, groups, seen=None):
    seen = set() if seen is None else seen
    calls = set()
    for n in names:
        if n.startswith("@"):
            if n not in seen:
                seen.add(n)
                calls |= expand(groups.get(n, []), groups, seen)
        else:
            calls.add(n)
    return calls


groups = syscall_groups()
allowed, denied = set(), set()
for value in settings("SystemCallFilter"):
    if value.startswith("~"):
        denied |= expand(value[1:].split(), groups)
    else:
        allowed |= expand(value.split(), groups)
allowed -= denied
families = set(" ".join(settings("RestrictAddressFamilies")).split())
namespaces = set(" ".join(settings("RestrictNamespaces")).split())

NAMESPACES = {"NEWUSER": "user", "NEWNET": "net", "NEWIPC": "ipc", "NEWUTS": "uts", "NEWNS": "mnt",
              "NEWPID": "pid", "NEWCGROUP": "cgroup", "NEWTIME": "time"}
used, refused, sockets, unshares = set(), set(), set(), set()
call = re.compile(r"^\d+\s+(?:<\.\.\. )?([a-z_0-9]+)\(")
for line in open(trace, errors="replace"):
    m = call.match(line)
    if not m or "resumed>" in line or line.split()[1].startswith("+++") or line.split()[1].startswith("---"):
        continue
    name = m.group(1)
    used.add(name)
    if name == "socket":
        fam = re.search(r"socket\((AF_[A-Z0-9]+)", line)
        if fam:
            sockets.add(fam.group(1))
    if name in ("unshare", "clone", "clone3"):
        unshares |= {NAMESPACES.get(f, f) for f in re.findall(r"CLONE_(NEW[A-Z]+)", line)}
for name in sorted(used):
    if name not in allowed:
        refused.add(name)

print("   %d distinct system calls traced; the unit allows %d" % (len(used), len(allowed)))
print("   refused by SystemCallFilter=: %s" % (", ".join(sorted(refused)) or "none"))
print("   socket families: %s (unit: %s)" % (", ".join(sorted(sockets)), ", ".join(sorted(families))))
print("   namespaces made: %s (unit: %s)" % (", ".join(sorted(unshares)) or "none", ", ".join(sorted(namespaces))))
bad = bool(refused) or not sockets <= families or not unshares <= namespaces
sys.exit(1 if bad else 0)
