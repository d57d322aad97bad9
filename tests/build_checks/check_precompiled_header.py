#!/usr/bin/env python3
"""Checks that the test drivers' compiler really reads their precompiled header.

GCC takes a precompiled header only when it is the first thing a translation unit includes; when
anything comes before it (a forced -include of another header, say), GCC reads the header's text
instead and says nothing, even under -Winvalid-pch. The build then still works, only slower.
This compiles one test driver as the build does (its command from compile_commands.json), with -H
and -fsyntax-only, and fails unless the first header GCC reports is the .gch, marked '!' (used).

Usage: check_precompiled_header.py BUILD_DIR SOURCE_SUFFIX...  (the first one the build compiles:
a unity batch, or a file of a build without them)
"""
import json
import os
import re
import shlex
import subprocess
import sys


def main() -> int:
    build_dir, suffixes = sys.argv[1], sys.argv[2:]
    with open(f"{build_dir}/compile_commands.json", encoding="utf-8") as f:
        commands = json.load(f)
    entries = [e for suffix in suffixes for e in commands if e["file"].endswith(suffix)]
    if not entries:
        print(f"check_precompiled_header: no compile command for {suffixes} in {build_dir}")
        return 1
    entry = entries[0]
    suffix = entry["file"]
    args = shlex.split(entry["command"]) if "command" in entry else list(entry["arguments"])
    if "-o" in args:
        at = args.index("-o")
        del args[at : at + 2]
    # The compiler launcher (ccache) would answer from its cache without printing the headers.
    compiler = re.compile(r"(c\+\+|g\+\+|gcc|clang\+\+|clang)(-[0-9.]+)?$")
    while args and not compiler.search(os.path.basename(args[0])):
        args.pop(0)
    if not args:
        print(f"check_precompiled_header: no compiler in the command of {entry['file']}")
        return 1
    run = subprocess.run(args + ["-H", "-fsyntax-only"], cwd=entry["directory"],
                         capture_output=True, text=True, check=False)
    if run.returncode != 0:
        print(run.stderr[-4000:])
        return 1
    headers = [line for line in run.stderr.splitlines() if line[:1] in ".!x"]
    if not headers:
        print("check_precompiled_header: the compiler reported no header")
        return 1
    first = headers[0]
    if first.startswith("! ") and first.endswith(".gch"):
        print(f"{suffix}: precompiled header used ({first[2:]})")
        return 0
    print(f"{suffix}: the precompiled header is not used; the first header read is {first!r}")
    print("(GCC takes a .gch only as the first include: is something included ahead of it?)")
    return 1


if __name__ == "__main__":
    sys.exit(main())
