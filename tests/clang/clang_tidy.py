#!/usr/bin/env python3
"""The lint check of CI: clang-tidy with the root .clang-tidy over rtmini's host sources, by
their compile_commands.json entries. Fails on any finding (.clang-tidy makes every enabled check
an error); exit 77 (ctest: skipped) when clang-tidy is absent.

Which files: those whose path starts with one of PREFIX... (relative to SOURCE_DIR), each
once (the core unit tests compile some files twice, for two backends).

Units with the same flags are checked in batches, as clang_syntax.py does (one translation unit
including each, so the Kokkos headers are parsed and matched once per batch: 2.5 s for 8 units
against 3 s for one alone). The .clang-tidy header filter reports findings in the included
units as in their own runs. A batch with any finding or error is checked again unit by unit,
and the verdict is the unit-by-unit one.

Usage: clang_tidy.py BUILD_DIR SOURCE_DIR [-j N] PREFIX...
"""
import concurrent.futures
import json
import os
import shutil
import subprocess
import sys
import time

import clang_syntax


def parse(argv):
    build, source, rest = argv[1], os.path.realpath(argv[2]), argv[3:]
    jobs = 2
    if len(rest) >= 2 and rest[0] == "-j":
        jobs, rest = int(rest[1]), rest[2:]
    return build, source, jobs, rest


def tidy_units(entries, source, prefixes):
    """The compile_commands.json entries under the prefixes, one per source file."""
    seen, units = set(), []
    for e in entries:
        path = os.path.realpath(e["file"])
        if path in seen or not any(os.path.relpath(path, source).startswith(pre) for pre in prefixes):
            continue
        seen.add(path)
        units.append(e)
    return units


def main():
    build, source, jobs, prefixes = parse(sys.argv)
    tidy = shutil.which("clang-tidy")
    if not tidy:
        print("SKIP: clang-tidy not found (apt-get install clang-tidy)")
        return 77
    with open(os.path.join(build, "compile_commands.json")) as f:
        units = tidy_units(json.load(f), source, prefixes)
    if not units:
        print(f"FAIL: no translation unit under {' '.join(prefixes)} in compile_commands.json")
        return 1
    # The batch files live in the build directory, which need not be under the source tree:
    # name the configuration rather than rely on clang-tidy finding it above the file.
    config = os.path.join(source, ".clang-tidy")
    batch_dir = os.path.join(os.path.realpath(build), "clang_tidy")
    os.makedirs(batch_dir, exist_ok=True)

    def run(directory, flags, path):
        r = subprocess.run([tidy, f"--config-file={config}", "--quiet", path, "--", *flags],
                           cwd=directory, capture_output=True, text=True)
        # Findings print as "file:line:col: warning|error: ... [check]"; the counts of
        # suppressed third-party findings go to stderr and are not findings.
        found = [line for line in r.stdout.splitlines() if ": warning: " in line or ": error: " in line]
        return r.returncode != 0 or bool(found), r.stdout + r.stderr

    def check_batch(numbered):
        number, (directory, flags, files) = numbered
        if len(files) > 1:
            batch = os.path.join(batch_dir, f"batch_{number}.cpp")
            with open(batch, "w") as f:
                f.writelines(clang_syntax.batch_source(files))
            bad, _ = run(directory, flags, batch)
            if not bad:
                return []
        failures = []
        for path in files:
            bad, out = run(directory, flags, path)
            if bad:
                failures.append((path, out))
        return failures

    start, failed = time.monotonic(), 0
    work = list(enumerate(clang_syntax.batches(units)))
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        for failures in pool.map(check_batch, work):
            for path, out in failures:
                failed += 1
                print(f"FAIL {os.path.relpath(path, source)}\n{out}")
    print(f"{len(units) - failed} of {len(units)} files clean under clang-tidy "
          f"(.clang-tidy of {source}; {len(work)} batches) in {time.monotonic() - start:.0f} s")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
