#!/usr/bin/env python3
# soak_memory.py - drives a running lucentd with mixed traffic (renders of many sizes up to its limit,
# cache hits, uploads and renders of uploaded meshes, bad requests) and samples its resident memory.
# Usage: soak_memory.py BASE_URL PID REQUESTS [--seed N] [--workers N]; prints one JSON line per quarter.
import argparse
import http.client
import json
import random
import threading
import time
import urllib.parse

MATERIALS = ["marble", "skin1", "skimmilk", "ketchup", "apple", "chicken1", "cream", "potato"]
METHODS = ["five", "single", "auto"]
MESHES = ["sphere", "torus", "protrusion"]


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    raise RuntimeError("no VmRSS")


def obj_bytes(rng):
    """A small closed tetrahedron with jittered corners: new bytes, so a new import."""
    p = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    p = [tuple(c + rng.uniform(-0.2, 0.2) for c in v) for v in p]
    lines = ["v %.6f %.6f %.6f" % v for v in p]
    lines += ["f 1 3 2", "f 1 2 4", "f 1 4 3", "f 2 3 4"]
    return ("\n".join(lines) + "\n").encode()


def render_query(rng, max_size):
    size = min(rng.choice([16, 24, 32, 48, 64, 96, 128, 192, 256, 384, max_size]), max_size)
    mesh = rng.choice(MESHES)
    q = {"mesh": mesh, "preset": rng.choice(MATERIALS), "w": size, "h": rng.choice([size, max(16, size // 2)]),
         "method": rng.choice(METHODS), "format": rng.choice(["png", "png", "png", "exr"])}
    if rng.random() < 0.5:
        q["mesh_triangles"] = rng.choice([1000, 5000, 20000])
    if rng.random() < 0.3:
        q["light_dir"] = "%d,%d,%d" % (rng.choice([-1, 0, 1]), 1, rng.choice([-1, 1]))
    return "/v1/render?" + urllib.parse.urlencode(q)


BAD = [
    ("GET", "/v1/render?w=abc", None, {}),
    ("GET", "/v1/render?w=99999", None, {}),
    ("GET", "/v1/render?mesh=nosuch", None, {}),
    ("GET", "/v1/render?w=16%00x", None, {}),
    ("GET", "/v1/render?zzz=1", None, {}),
    ("POST", "/v1/render", b'{"width": ', {"Content-Type": "application/json"}),
    ("POST", "/v1/render", b'{"width": NaN}', {"Content-Type": "application/json"}),
    ("POST", "/v1/render", b'{"material": {"sigma_a": [-1, 0, 0]}}', {"Content-Type": "application/json"}),
    ("POST", "/v1/meshes", b"solid x\nendsolid", {"Content-Type": "model/stl"}),
    ("POST", "/v1/meshes", b"\x00" * 300, {}),
    ("GET", "/v1/meshes/" + "0" * 64, None, {}),
    ("GET", "/nowhere", None, {}),
    ("DELETE", "/v1/render", None, {}),
]


class Driver:
    def __init__(self, base, pid, total, seed, workers, max_size, renders, meshes):
        u = urllib.parse.urlparse(base)
        self.host, self.port = u.hostname, u.port
        self.pid, self.total, self.workers = pid, total, workers
        self.rng = random.Random(seed)
        # Finite pools, drawn from again and again: most renders and uploads repeat (cache hits, meshes
        # already stored), as a gallery's traffic does; the first of each is new work.
        pool = random.Random(seed)
        self.meshes = [obj_bytes(pool) for _ in range(meshes)]
        self.renders = [render_query(pool, max_size) for _ in range(renders)]
        self.lock = threading.Lock()
        self.sent = 0
        self.statuses = {}
        self.uploaded = []
        self.unexpected = []
        self.samples = []  # (request index, rss KiB)

    def next_request(self):
        with self.lock:
            if self.sent >= self.total:
                return None
            self.sent += 1
            r = self.rng.random()
            if r < 0.45:
                req = ("GET", self.rng.choice(self.renders), None, {}, "render")
            elif r < 0.50 and self.uploaded:  # an uploaded mesh, rendered
                q = "/v1/render?mesh=%s&w=64&h=64&preset=%s" % (self.rng.choice(self.uploaded),
                                                                  self.rng.choice(MATERIALS))
                req = ("GET", q, None, {}, "render")
            elif r < 0.55:
                req = ("POST", "/v1/meshes", self.rng.choice(self.meshes), {"Content-Type": "model/obj"}, "upload")
            elif r < 0.65:
                req = ("GET", "/healthz", None, {}, "probe")
            else:
                m, p, b, h = self.rng.choice(BAD)
                req = (m, p, b, h, "bad")
            return self.sent, req

    def record(self, index, kind, status, body):
        with self.lock:
            self.statuses[status] = self.statuses.get(status, 0) + 1
            ok = {"render": (200,), "upload": (200, 201, 503), "probe": (200,), "bad": (*range(400, 500), 503)}[kind]
            if status not in ok and len(self.unexpected) < 10:
                self.unexpected.append((kind, status, body[:200].decode("utf-8", "replace")))
            if kind == "upload" and status in (200, 201):
                mesh_id = json.loads(body)["id"]
                if mesh_id not in self.uploaded:
                    self.uploaded.append(mesh_id)

    def worker(self):
        conn = http.client.HTTPConnection(self.host, self.port, timeout=120)
        while True:
            item = self.next_request()
            if item is None:
                break
            index, (method, path, body, headers, kind) = item
            for attempt in range(2):
                try:
                    conn.request(method, path, body=body, headers=headers)
                    resp = conn.getresponse()
                    data = resp.read()
                    if resp.getheader("Connection", "").lower() == "close":
                        conn.close()
                    break
                except (http.client.HTTPException, OSError):
                    conn.close()
                    conn = http.client.HTTPConnection(self.host, self.port, timeout=120)
                    if attempt:
                        raise
            self.record(index, kind, resp.status, data)
            if index % 25 == 0:
                with self.lock:
                    self.samples.append((index, rss_kib(self.pid)))
        conn.close()

    def run(self):
        t0 = time.monotonic()
        threads = [threading.Thread(target=self.worker) for _ in range(self.workers)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        return time.monotonic() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("pid", type=int)
    ap.add_argument("requests", type=int)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--workers", type=int, default=4)
    ap.add_argument("--max-size", type=int, default=512)
    ap.add_argument("--renders", type=int, default=150, help="distinct render queries")
    ap.add_argument("--meshes", type=int, default=40, help="distinct meshes uploaded")
    a = ap.parse_args()
    d = Driver(a.base, a.pid, a.requests, a.seed, a.workers, a.max_size, a.renders, a.meshes)
    secs = d.run()
    samples = sorted(d.samples)
    n = len(samples)
    quarter = [samples[i * n // 4:(i + 1) * n // 4] for i in range(4)]
    report = {
        "requests": d.sent, "seconds": round(secs, 1), "statuses": d.statuses,
        "rss_kib_quarter_max": [max(s for _, s in q) for q in quarter],
        "rss_kib_end": rss_kib(a.pid), "unexpected": d.unexpected,
    }
    print(json.dumps(report))


if __name__ == "__main__":
    main()
