#!/usr/bin/env python3
"""Runs every shell command block of README.md (then of docs/*.md) as written (issue 22: "every README command
copy-paste runnable from the repository root").

A block is a fenced code block whose info string starts with `sh`. The words after `sh` mark it:

  ```sh            run it, no server needed
  ```sh server     run it with a `slosh serve` running; the block reads the service's address from
                   SLOSH_URL (README commands write `${SLOSH_URL:-http://127.0.0.1:8080}`)
  ```sh redis      run it with a redis-server (started by this test on a free loopback port, no
                   persistence) whose URL is in SLOSH_REDIS_URL, and SLOSH_URL pointing at a
                   `slosh serve --cache $SLOSH_REDIS_URL` (another server than the `server` one)
  ```sh no-test    never run (e.g. `make run`, which does not return)
  ```sh <other>    needs something this test does not start (e.g. `nginx`): skipped, and listed as
                   skipped

Blocks of other languages (json, text, console, ...) are not run. The blocks run in order, each in
a fresh `bash -euo pipefail`, in one scratch directory laid out like the repository root: `build`
is a link to the build directory, `examples/` and `config/` are copies, so the README's relative
paths work and nothing is written into the source tree. HOME and XDG_STATE_HOME point into the
scratch directory (the plan store lands there, not in the user's home). One server is started (on
a free port, `--port 0 --port-file`) at the first `server` block and kept for the later ones, so
a block may use a key an earlier one planned. Any non-zero exit fails the test, naming the block's
file and line and showing its output.
"""
import argparse
import os
import socket
import re
import shutil
import subprocess
import sys
import tempfile
import time

KNOWN = {"server", "redis", "no-test"}


def blocks(readme):
    """(line, marks, text, shown key) of every ```sh block."""
    out, lines, i = [], readme.split("\n"), 0
    while i < len(lines):
        m = re.match(r"^```(\S*)\s*(.*)$", lines[i])
        if not m:
            i += 1
            continue
        lang, marks, start, body = m.group(1), m.group(2).split(), i + 1, []
        i += 1
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        i += 1
        if lang == "sh":
            out.append((start, marks, "\n".join(body) + "\n", shown_key(lines, i)))
    return out


def shown_key(lines, i):
    """The recipe key printed by the ```text block right after line i (the output the README shows
    for the block above it), or None: a shown key must be the one the command prints."""
    while i < len(lines) and not lines[i].strip():
        i += 1
    if i >= len(lines) or not lines[i].startswith("```text"):
        return None
    i += 1
    while i < len(lines) and not lines[i].startswith("```"):
        m = re.match(r"^key\s+([0-9a-f]{32})\b", lines[i])
        if m:
            return m.group(1)
        i += 1
    return None


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Redis:
    """A redis-server on a free loopback port, nothing persisted; its URL in self.url."""

    def __init__(self, scratch):
        port = free_port()
        self.url = f"redis://127.0.0.1:{port}/0"
        self.log = open(os.path.join(scratch, ".redis.log"), "w")
        self.proc = subprocess.Popen(
            ["redis-server", "--port", str(port), "--bind", "127.0.0.1", "--save", "",
             "--appendonly", "no", "--dir", scratch], stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 10
        while time.time() < deadline:
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=0.2) as s:
                    s.sendall(b"PING\r\n")
                    if s.recv(16).startswith(b"+PONG"):
                        return
            except OSError:
                pass
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        raise RuntimeError("redis-server did not start")

    def stop(self):
        self.proc.kill()
        self.proc.wait()
        self.log.close()


class Server:
    def __init__(self, slosh, scratch, env, name="server", extra=()):
        self.port_file = os.path.join(scratch, f".{name}.port")
        self.log = open(os.path.join(scratch, f".{name}.log"), "w")
        self.proc = subprocess.Popen(
            [slosh, "serve", "--port", "0", "--port-file", self.port_file, "--workers", "2",
             *extra], cwd=scratch, env=env, stdout=self.log, stderr=subprocess.STDOUT)
        deadline = time.time() + 30
        while time.time() < deadline:
            if os.path.exists(self.port_file):
                text = open(self.port_file).read()
                if text.endswith("\n"):
                    self.url = "http://127.0.0.1:" + text.strip()
                    return
            if self.proc.poll() is not None:
                break
            time.sleep(0.05)
        raise RuntimeError("slosh serve did not start")

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
        self.log.close()


def scratch_tree(source, build_dir):
    scratch = tempfile.mkdtemp(prefix="slosh_readme_")
    os.symlink(os.path.abspath(build_dir), os.path.join(scratch, "build"))
    for d in ("examples", "config"):
        shutil.copytree(os.path.join(source, d), os.path.join(scratch, d))
    os.makedirs(os.path.join(scratch, ".home"))
    return scratch


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True, help="repository root (README.md, examples/)")
    ap.add_argument("--slosh", required=True, help="the built slosh binary")
    args = ap.parse_args()
    failures, found = [], []
    docs = sorted(f for f in os.listdir(os.path.join(args.source, "docs")) if f.endswith(".md"))
    for name in ["README.md"] + ["docs/" + f for f in docs]:
        text = open(os.path.join(args.source, name), encoding="utf-8").read()
        if "../shared" in text:
            failures.append(f"{name} refers to ../shared: the repository must stand alone")
        found += [(f"{name}:{line}", marks, body, key) for line, marks, body, key in blocks(text)]
    if not any(where.startswith("README.md:") for where, _, _, _ in found):
        failures.append("README.md has no ```sh block")
    scratch = scratch_tree(args.source, os.path.dirname(os.path.abspath(args.slosh)))
    home = os.path.join(scratch, ".home")
    env = dict(os.environ, HOME=home, XDG_STATE_HOME=os.path.join(home, "state"))
    env.pop("SLOSH_URL", None)
    env.pop("SLOSH_CACHE", None)
    server = redis = redis_server = None
    ran = skipped = 0
    try:
        for line, marks, text, key in found:
            unknown = [m for m in marks if m not in KNOWN]
            if "no-test" in marks or unknown:
                why = "no-test" if "no-test" in marks else "needs " + ", ".join(unknown)
                print(f"{line}: skipped ({why})")
                skipped += 1
                continue
            block_env = dict(env)
            if "server" in marks:
                if server is None:
                    server = Server(os.path.abspath(args.slosh), scratch, env)
                block_env["SLOSH_URL"] = server.url
            if "redis" in marks:
                if redis is None:
                    redis = Redis(scratch)
                    redis_server = Server(os.path.abspath(args.slosh), scratch, env, "redis-server",
                                          ["--cache", redis.url])
                block_env["SLOSH_REDIS_URL"] = redis.url
                block_env["SLOSH_URL"] = redis_server.url
            started = time.time()
            r = subprocess.run(["bash", "-euo", "pipefail", "-c", text], cwd=scratch,
                               env=block_env, capture_output=True, text=True, timeout=600)
            ran += 1
            print(f"{line}: exit {r.returncode} in {time.time() - started:.1f} s"
                  + "".join(f" ({m})" for m in marks))
            if r.returncode != 0:
                failures.append(f"{line}: exit {r.returncode}\n--- block\n{text}"
                                f"--- stdout\n{r.stdout[-3000:]}--- stderr\n{r.stderr[-3000:]}")
            printed = re.search(r"^key\s+([0-9a-f]{32})\b", r.stdout, re.M)
            if key and (printed is None or printed.group(1) != key):
                failures.append(f"{line}: the README shows key {key}, the command printed "
                                f"{printed.group(1) if printed else 'none'}")
    finally:
        for running in (server, redis_server, redis):
            if running is not None:
                running.stop()
    leftovers = [f for f in os.listdir(scratch) if f.startswith("slosh-plans.sqlite")]
    if leftovers:
        failures.append("a command left a plan store in the working directory: " + ", ".join(leftovers))
    for f in failures:
        print("FAIL " + f, file=sys.stderr)
    print(f"{ran} blocks ran, {skipped} skipped, {len(failures)} failures")
    if not failures:
        shutil.rmtree(scratch, ignore_errors=True)
    else:
        print(f"scratch directory kept: {scratch}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
