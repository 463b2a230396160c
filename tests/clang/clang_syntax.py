#!/usr/bin/env python3
"""The Clang build of CI, kept cheap: every translation unit of compile_commands.json that
belongs to rtmini is checked by Debian's clang++ with -fsyntax-only and the project's warning
set as errors (no code generation, no link). Exit 77 (ctest: skipped) when clang++ is absent.

Usage: clang_syntax.py BUILD_DIR SOURCE_DIR [-j N]
"""
import concurrent.futures
import json
import os
import shlex
import shutil
import subprocess
import sys

WARNINGS = ["-Wall", "-Wextra", "-Wshadow", "-Werror"]
# GCC-only flags in the GCC build's command lines that Clang rejects or warns about.
DROP = {"-fno-fat-lto-objects"}


def clang_command(entry, clang):
    args = entry.get("arguments") or shlex.split(entry["command"])
    # The first word is the compiler, possibly behind a launcher (ccache).
    while args and os.path.basename(args[0]) in ("ccache", "sccache"):
        args = args[1:]
    out, skip = [clang], False
    for a in args[1:]:
        if skip:
            skip = False
            continue
        if a == "-o":
            skip = True
            continue
        if a in DROP or a == "-c":
            continue
        out.append(a)
    return out + ["-fsyntax-only"] + WARNINGS


def main():
    build, source = sys.argv[1], os.path.realpath(sys.argv[2])
    jobs = int(sys.argv[4]) if len(sys.argv) > 4 and sys.argv[3] == "-j" else 2
    clang = shutil.which("clang++")
    if not clang:
        print("SKIP: clang++ not found (apt-get install clang)")
        return 77
    with open(os.path.join(build, "compile_commands.json")) as f:
        entries = json.load(f)
    units = [e for e in entries
             if os.path.realpath(e["file"]).startswith(source + os.sep)
             and "/.deps/" not in e["file"] and e["file"].endswith(".cpp")]
    if not units:
        print("FAIL: no rtmini translation units in compile_commands.json")
        return 1

    def check(entry):
        r = subprocess.run(clang_command(entry, clang), cwd=entry["directory"],
                           capture_output=True, text=True)
        return entry["file"], r.returncode, r.stderr

    failed = 0
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        for path, code, err in pool.map(check, units):
            if code != 0:
                failed += 1
                print(f"FAIL {os.path.relpath(path, source)}\n{err}")
    print(f"{len(units) - failed} of {len(units)} translation units clean under clang++ "
          f"{' '.join(WARNINGS)}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
