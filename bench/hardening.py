#!/usr/bin/env python3
"""Loopback hardening figures of `slosh serve` (README "Limits and hardening").

Starts its own server and measures, each bounded in count and time:
  slow     /healthz latency with 64 trickling connections (one header byte every 2 s) and 16 idle
           keep-alive connections open;
  fair     32 concurrent clients on a cached plan for a few seconds: every client's first answer,
           requests/s, p50/p99;
  memory   RSS after 20 maximal series requests and a 32 MiB chunked body;
  batch    a 1000-item batch against --workers 2 --queue 4;
  shutdown SIGTERM with 4 trickling clients connected: seconds to exit.
Usage: bench/hardening.py [build-dir]
"""
import http.client
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
FORMAT = {"container": {"radius_mm": 48.5}, "fill_height_mm": 82, "fluid": "water",
          "stroke_mm": 800, "motion_time_s": 1.0}


def start(extra=()):
    d = tempfile.mkdtemp()
    port_file = os.path.join(d, "port")
    p = subprocess.Popen([os.path.join(BUILD, "slosh"), "serve", "--port", "0", "--port-file",
                          port_file, "--cache", os.path.join(d, "plans.sqlite"), *extra],
                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(200):
        if os.path.exists(port_file):
            return p, int(open(port_file).read())
        time.sleep(0.05)
    raise RuntimeError("no port")


def rss_mib(pid):
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def post(port, path, body, timeout=120):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=timeout)
    c.request("POST", path, body=json.dumps(body), headers={"Content-Type": "application/json"})
    r = c.getresponse()
    data = r.read()
    c.close()
    return r.status, data


def healthz_ms(port):
    t = time.monotonic()
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
    c.request("GET", "/healthz")
    ok = c.getresponse().status == 200
    c.close()
    return (time.monotonic() - t) * 1e3 if ok else float("inf")


def trickler(port, stop, seconds_per_byte=2.0):
    s = socket.create_connection(("127.0.0.1", port))
    line = b"GET /healthz HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"a" * 10000
    i = 0
    try:
        while not stop.is_set() and i < len(line):
            s.send(line[i:i + 1])
            i += 1
            stop.wait(seconds_per_byte)
    except OSError:
        pass
    s.close()


def slow(port):
    stop = threading.Event()
    threads = [threading.Thread(target=trickler, args=(port, stop)) for _ in range(64)]
    for t in threads:
        t.start()
    idle = []
    for _ in range(16):
        c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
        c.request("GET", "/healthz")
        c.getresponse().read()
        idle.append(c)
    time.sleep(1.0)
    samples = [healthz_ms(port) for _ in range(10)]
    stop.set()
    for t in threads:
        t.join()
    for c in idle:
        c.close()
    print(f"slow: /healthz with 64 trickling + 16 idle keep-alive connections: "
          f"max {max(samples):.1f} ms, median {sorted(samples)[5]:.1f} ms over 10")


def fair(port, seconds=5.0, clients=32):
    body = json.dumps({"format": FORMAT, "strategy": "multi_notch"})
    post(port, "/v1/plans", json.loads(body))
    first, latencies, counts = [None] * clients, [], [0] * clients
    lock = threading.Lock()
    start = time.monotonic()

    def client(i):
        c = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
        while time.monotonic() - start < seconds:
            t = time.monotonic()
            c.request("POST", "/v1/plans", body=body, headers={"Content-Type": "application/json"})
            r = c.getresponse()
            r.read()
            now = time.monotonic()
            with lock:
                latencies.append(now - t)
                counts[i] += 1
                if first[i] is None:
                    first[i] = now - start
        c.close()

    threads = [threading.Thread(target=client, args=(i,)) for i in range(clients)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    latencies.sort()
    served = sum(1 for f in first if f is not None)
    print(f"fair: {served}/{clients} clients served, slowest first answer "
          f"{max(f for f in first if f is not None) * 1e3:.1f} ms, "
          f"{len(latencies) / seconds:.0f} requests/s (Python clients), "
          f"p50 {latencies[len(latencies) // 2] * 1e3:.2f} ms, "
          f"p99 {latencies[int(len(latencies) * 0.99)] * 1e3:.2f} ms")


def memory(port, pid):
    before = rss_mib(pid)
    peak = before
    for i in range(20):
        body = {"format": dict(FORMAT, stroke_mm=800 + i), "strategy": "baseline",
                "options": {"rest_time_s": 3.9}, "sample_period_s": 1e-4}
        status, data = post(port, "/v1/plans", body)
        assert status == 200, data[:300]
        peak = max(peak, rss_mib(pid))
    s = socket.create_connection(("127.0.0.1", port))
    s.sendall(b"POST /v1/plans HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
              b"Transfer-Encoding: chunked\r\n\r\n")
    chunk = b"%x\r\n" % 65536 + b" " * 65536 + b"\r\n"
    sent = 0
    try:
        while sent < 32 << 20:
            s.sendall(chunk)
            sent += 65536
    except OSError:
        pass
    s.close()
    time.sleep(0.5)
    peak = max(peak, rss_mib(pid))
    print(f"memory: RSS {before:.0f} MiB before, {peak:.0f} MiB peak through 20 series of "
          f"{len(data) / 1e6:.1f} MB and a 32 MiB chunked body (cut at the limit after "
          f"{sent >> 20} MiB sent), {rss_mib(pid):.0f} MiB after")


def batch():
    p, port = start(["--workers", "2", "--queue", "4"])
    items = [{"format": dict(FORMAT, stroke_mm=300 + i), "strategy": "multi_notch"}
             for i in range(1000)]
    t = time.monotonic()
    status, data = post(port, "/v1/plans/batch", {"requests": items}, timeout=600)
    n = sum(1 for r in json.loads(data)["results"] if "plan" in r)
    print(f"batch: 1000 items against --workers 2 --queue 4: status {status}, {n} plans, "
          f"{time.monotonic() - t:.1f} s; /healthz after {healthz_ms(port):.1f} ms")
    p.send_signal(signal.SIGTERM)
    p.wait(30)


def shutdown(p, port):
    stop = threading.Event()
    threads = [threading.Thread(target=trickler, args=(port, stop)) for _ in range(4)]
    for t in threads:
        t.start()
    time.sleep(1.0)
    t = time.monotonic()
    p.send_signal(signal.SIGTERM)
    code = p.wait(60)
    print(f"shutdown: SIGTERM with 4 trickling clients: exit {code} after "
          f"{time.monotonic() - t:.2f} s")
    stop.set()
    for t in threads:
        t.join()


def main():
    p, port = start()
    try:
        slow(port)
        fair(port)
        memory(port, p.pid)
        shutdown(p, port)
    finally:
        if p.poll() is None:
            p.kill()
    batch()


if __name__ == "__main__":
    main()
