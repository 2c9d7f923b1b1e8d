#!/usr/bin/env python3
"""test_lucentd_notify.py - lucentd as systemd's Type=notify sees it: a datagram socket bound here as
$NOTIFY_SOCKET receives the status while warming, READY=1 (when /readyz answers 200), the queue depth,
watchdog pings at half of $WATCHDOG_USEC, STOPPING=1 on SIGTERM, each from lucentd's own pid; an
abstract socket name works and a bad one is only a warning. With --faults (a fault-injection build), a
render worker stuck in the driver stops the pings. Usage: test_lucentd_notify.py LUCENTD [--faults]"""
import os
import re
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.request

LUCENTD = sys.argv[1]
FAULTS = "--faults" in sys.argv[2:]
WORK = tempfile.mkdtemp(prefix="lucent-notify-")
results = {"passed": 0, "failed": 0}


def check(name, ok):
    results["passed" if ok else "failed"] += 1
    print(("ok   " if ok else "FAIL ") + name, flush=True)


class Manager:
    """The service manager's end: every datagram with its arrival time and the sender's pid."""

    def __init__(self, address):
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
        self.sock.setsockopt(socket.SOL_SOCKET, socket.SO_PASSCRED, 1)
        self.sock.bind(address)
        self.sock.settimeout(0.1)
        self.messages, self.stop = [], False
        self.thread = threading.Thread(target=self.read, daemon=True)
        self.thread.start()

    def read(self):
        cred_size = struct.calcsize("3i")
        while not self.stop:
            try:
                data, anc, _, _ = self.sock.recvmsg(4096, socket.CMSG_SPACE(cred_size))
            except socket.timeout:
                continue
            pid = -1
            for level, kind, cdata in anc:
                if level == socket.SOL_SOCKET and kind == socket.SCM_CREDENTIALS:
                    pid = struct.unpack("3i", cdata[:cred_size])[0]
            self.messages.append((time.monotonic(), pid, data.decode(errors="replace")))

    def wait_for(self, key, timeout=60.0):
        """The first message holding KEY (a line, or a prefix of one), waiting for it."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            for m in list(self.messages):
                if any(line.startswith(key) for line in m[2].split("\n")):
                    return m
            time.sleep(0.02)
        return None

    def close(self):
        self.stop = True
        self.thread.join()
        self.sock.close()


def start(name, env_extra, *args):
    log = open(os.path.join(WORK, name + ".log"), "w+")
    env = dict(os.environ, **env_extra)
    p = subprocess.Popen([LUCENTD, "--port", "0", "--store-dir", os.path.join(WORK, "store-" + name), *args],
                         env=env, stderr=log, stdout=subprocess.DEVNULL)
    base = None
    for _ in range(600):
        m = re.search(r"listening on (http://127\.0\.0\.1:\d+)", open(log.name).read())
        if m:
            base = m.group(1)
            break
        time.sleep(0.05)
    return p, base, log.name


def get(url, timeout=120):
    try:
        with urllib.request.urlopen(url, timeout=timeout) as r:
            r.read()
            return r.status
    except urllib.error.HTTPError as e:
        return e.code
    except OSError:
        return -1


def lines_of(messages):
    return [line for _, _, text in messages for line in text.split("\n")]


# ---- A: a socket path, a 1 s watchdog ----
mgr = Manager(os.path.join(WORK, "notify"))
t_start = time.monotonic()
proc, base, log = start("A", {"NOTIFY_SOCKET": os.path.join(WORK, "notify"), "WATCHDOG_USEC": "1000000"},
                        "--drain-timeout", "60")
ready = mgr.wait_for("READY=1")
readyz = get(base + "/readyz") if base else -1
first = mgr.messages[0][2] if mgr.messages else ""
check("before READY=1: %r" % first.split("\n")[0], first.startswith("STATUS=warming the renderer"))
check("READY=1 after %.1f s, with /readyz %d then, MAINPID and a status: %r"
      % ((ready[0] - t_start) if ready else -1, readyz, ready[2].replace("\n", " | ") if ready else None),
      ready is not None and readyz == 200 and ("MAINPID=%d" % proc.pid) in ready[2]
      and "STATUS=serving on " in ready[2])
time.sleep(2.5)
pings = [m[0] for m in mgr.messages if m[2] == "WATCHDOG=1" and m[0] > ready[0]] if ready else []
gaps = [b - a for a, b in zip(pings, pings[1:])]
check("watchdog: %d pings in the 2.5 s after READY, largest gap %.2f s (WATCHDOG_USEC 1 s: at most 1 s)"
      % (len(pings), max(gaps) if gaps else -1), len(pings) >= 4 and gaps and max(gaps) < 1.0)
# A slow render (method reference) shows in the status line as queued or running.
answers = {}
render_url = base + "/v1/render?w=128&h=128&method=reference&reference_points=20000"  # 3.3 s here, 2026-12-07
slow = threading.Thread(target=lambda: answers.__setitem__("slow", get(render_url)))
slow.start()
t_render = time.monotonic()
while time.monotonic() - t_render < 30 and slow.is_alive():
    busy = [m for m in mgr.messages if m[0] > t_render and "(1 running)" in m[2]]
    if busy:
        break
    time.sleep(0.05)
check("during a render the status says so: %r" % (busy[0][2] if busy else None), bool(busy))
slow.join()
# SIGTERM while a render runs: STOPPING=1 with the depth, the render answered, exit 0.
slow = threading.Thread(target=lambda: answers.__setitem__("drained", get(render_url + "&exposure=1")))
t_submit = time.monotonic()
slow.start()
for _ in range(600):  # a status line sent after this render began, showing it running
    if any(m[0] > t_submit + 0.05 and "(1 running)" in m[2] for m in mgr.messages):
        break
    time.sleep(0.05)
t_term = time.monotonic()
proc.send_signal(signal.SIGTERM)
stopping = mgr.wait_for("STOPPING=1")
slow.join()
rc = proc.wait(timeout=120)
check("SIGTERM: %r %.2f s after it; the render in flight answered %s; exit %d"
      % (stopping[2].replace("\n", " | ") if stopping else None, (stopping[0] - t_term) if stopping else -1,
         answers.get("drained"), rc),
      stopping is not None and "STATUS=draining: 1 renders queued or running" in stopping[2]
      and answers.get("drained") == 200 and rc == 0)
order = [line.split("=")[0] for line in lines_of(mgr.messages) if line in ("READY=1", "STOPPING=1")]
senders = {m[1] for m in mgr.messages}
check("READY=1 once, then STOPPING=1 once (%s); all %d messages from lucentd's pid %d (senders %s)"
      % (",".join(order), len(mgr.messages), proc.pid, sorted(senders)),
      order == ["READY", "STOPPING"] and senders == {proc.pid})
mgr.close()

# ---- B: an abstract socket name; C: a NOTIFY_SOCKET that is neither is a warning, not a failure ----
name = "@lucent-notify-test-%d" % os.getpid()
mgr = Manager("\0" + name[1:])
proc, base, log = start("B", {"NOTIFY_SOCKET": name})
ready = mgr.wait_for("READY=1")
check("abstract socket %s: READY=1 arrives, no watchdog pings without WATCHDOG_USEC (%d)"
      % (name, sum(m[2] == "WATCHDOG=1" for m in mgr.messages)),
      ready is not None and not any(m[2] == "WATCHDOG=1" for m in mgr.messages))
proc.send_signal(signal.SIGTERM)
check("B: exit %d" % proc.wait(timeout=120), proc.returncode == 0)
mgr.close()
proc, base, log = start("C", {"NOTIFY_SOCKET": "relative/socket"})
for _ in range(600):
    if get(base + "/readyz", timeout=5) == 200 if base else False:
        break
    time.sleep(0.1)
warned = [line for line in open(log) if "NOTIFY_SOCKET" in line]
check("a bad NOTIFY_SOCKET: served anyway (/readyz %d), warned: %r"
      % (get(base + "/readyz") if base else -1, warned[0].strip()[-90:] if warned else None),
      bool(warned) and base is not None and get(base + "/readyz") == 200)
proc.send_signal(signal.SIGTERM)
proc.wait(timeout=120)

# ---- D: a render worker stuck in the driver (frame 2's wait never returns) stops the watchdog ----
if FAULTS:
    mgr = Manager(os.path.join(WORK, "notify-d"))
    proc, base, log = start("D", {"NOTIFY_SOCKET": os.path.join(WORK, "notify-d"), "WATCHDOG_USEC": "1000000",
                                  "LUCENT_FAULTS": "hang@2"}, "--render-timeout", "1")
    mgr.wait_for("READY=1")
    t0 = time.monotonic()
    code = get(base + "/v1/render?w=64&h=64")
    answered = time.monotonic() - t0
    stuck = mgr.wait_for("STATUS=render worker stuck", timeout=30)
    time.sleep(2.0)
    last_ping = max((m[0] for m in mgr.messages if m[2] == "WATCHDOG=1"), default=0.0)
    check("hung frame: %d after %.1f s; pings stop %.1f s after the render began (deadline 1 s + 5 s); "
          "none in the %.1f s since; status %r"
          % (code, answered, last_ping - t0, time.monotonic() - last_ping,
             stuck[2] if stuck else None),
          code == 503 and stuck is not None and 5.0 <= last_ping - t0 <= 8.0
          and time.monotonic() - last_ping > 2.0)
    proc.kill()
    proc.wait()
    mgr.close()

shutil.rmtree(WORK, ignore_errors=True)
print("%d passed, %d failed" % (results["passed"], results["failed"]))
sys.exit(1 if results["failed"] else 0)
