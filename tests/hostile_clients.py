#!/usr/bin/env python3
"""hostile_clients.py - clients that try to exhaust lucentd, for test_lucentd.sh. Prints one JSON line.

slowloris PORT N: N connections from 127.0.0.1 trickle a request's headers a byte at a time; reports how
  many the daemon closed at once (per-client limit), /healthz from 127.0.0.2 meanwhile, and how long until
  the daemon closed the trickling ones (the whole-request deadline).
bodies PORT LENGTH N: N uploads from distinct loopback addresses each declare LENGTH bytes and send 8; one
  more then reports the status line it gets, while the N are held open."""
import json, socket, subprocess, sys, time


def closed(s):
    s.setblocking(False)
    try:
        return s.recv(100) == b""
    except BlockingIOError:
        return False
    except OSError:
        return True


def slowloris(port, n):
    socks = []
    for _ in range(n):
        s = socket.create_connection(("127.0.0.1", port))
        s.sendall(b"GET /healthz HTTP/1.1\r\n")
        socks.append(s)
    time.sleep(0.5)
    held = [s for s in socks if not closed(s)]
    health = subprocess.run(["curl", "-s", "-o", "/dev/null", "-w", "%{http_code}", "--max-time", "5", "--interface",
                             "127.0.0.2", "http://127.0.0.1:%d/healthz" % port], capture_output=True, text=True).stdout
    t0, shut = time.time(), 0
    while time.time() - t0 < 30:
        for s in held:
            try:
                s.send(b"X")
            except OSError:
                pass
        shut = sum(closed(s) for s in held)
        if shut == len(held):
            break
        time.sleep(0.2)
    return {"refused_at_once": n - len(held), "held": len(held), "healthz_meanwhile": health,
            "closed_after_s": round(time.time() - t0 + 0.5, 1), "closed": shut}


def bodies(port, length, n):
    def upload(src):
        s = socket.socket()
        s.bind((src, 0))
        s.connect(("127.0.0.1", port))
        s.sendall(b"POST /v1/meshes HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: model/obj\r\n"
                  b"Content-Length: %d\r\n\r\nv 0 0 0\n" % length)
        return s
    held = [upload("127.0.0.%d" % (10 + i)) for i in range(n)]
    time.sleep(0.5)
    metric = subprocess.run(["curl", "-s", "http://127.0.0.1:%d/metrics" % port], capture_output=True,
                            text=True).stdout
    charged = [l.split()[1] for l in metric.splitlines() if l.startswith("lucentd_request_body_bytes ")]
    s = upload("127.0.0.%d" % (10 + n))
    s.settimeout(10)
    reply = s.recv(4096).decode(errors="replace")
    head, _, body = reply.partition("\r\n\r\n")
    retry = [l.split(":", 1)[1].strip() for l in head.split("\r\n") if l.lower().startswith("retry-after:")]
    for h in held:
        h.close()
    return {"status_line": head.split("\r\n")[0], "retry_after": retry[0] if retry else "",
            "type": json.loads(body).get("type", "") if body.startswith("{") else "",
            "charged_while_held": charged[0] if charged else ""}


if __name__ == "__main__":
    port = int(sys.argv[2])
    if sys.argv[1] == "slowloris":
        print(json.dumps(slowloris(port, int(sys.argv[3]))))
    else:
        print(json.dumps(bodies(port, int(sys.argv[3]), int(sys.argv[4]))))
