#!/usr/bin/env python3
"""The lint check of CI: clang-tidy with the root .clang-tidy over rtmini's host sources, by
their compile_commands.json entries. Fails on any finding (.clang-tidy makes every enabled check
an error); exit 77 (ctest: skipped) when clang-tidy is absent.

Which files: those whose path starts with one of PREFIX... (relative to SOURCE_DIR), each
once (the core unit tests compile some files twice, for two backends).

Usage: clang_tidy.py BUILD_DIR SOURCE_DIR [-j N] PREFIX...
"""
import concurrent.futures
import json
import os
import shutil
import subprocess
import sys
import time


def parse(argv):
    build, source, rest = argv[1], os.path.realpath(argv[2]), argv[3:]
    jobs = 2
    if len(rest) >= 2 and rest[0] == "-j":
        jobs, rest = int(rest[1]), rest[2:]
    return build, source, jobs, rest


def main():
    build, source, jobs, prefixes = parse(sys.argv)
    tidy = shutil.which("clang-tidy")
    if not tidy:
        print("SKIP: clang-tidy not found (apt-get install clang-tidy)")
        return 77
    with open(os.path.join(build, "compile_commands.json")) as f:
        entries = json.load(f)
    files = sorted({os.path.realpath(e["file"]) for e in entries})
    units = [p for p in files
             if any(os.path.relpath(p, source).startswith(pre) for pre in prefixes)]
    if not units:
        print(f"FAIL: no translation unit under {' '.join(prefixes)} in compile_commands.json")
        return 1

    def check(path):
        r = subprocess.run([tidy, "-p", build, "--quiet", path], capture_output=True, text=True)
        # Findings print as "file:line:col: warning|error: ... [check]"; the counts of
        # suppressed third-party findings go to stderr and are not findings.
        found = [line for line in r.stdout.splitlines() if ": warning: " in line or ": error: " in line]
        return path, r.returncode != 0 or bool(found), r.stdout + r.stderr

    start, failed = time.monotonic(), 0
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        for path, bad, out in pool.map(check, units):
            if bad:
                failed += 1
                print(f"FAIL {os.path.relpath(path, source)}\n{out}")
    print(f"{len(units) - failed} of {len(units)} files clean under clang-tidy "
          f"(.clang-tidy of {source}) in {time.monotonic() - start:.0f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
