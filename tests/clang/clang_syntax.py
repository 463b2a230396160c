#!/usr/bin/env python3
"""The Clang build of CI, kept cheap: every translation unit of compile_commands.json that
belongs to rtmini is checked by Debian's clang++ with -fsyntax-only and the project's warning
set as errors (no code generation, no link). Exit 77 (ctest: skipped) when clang++ is absent.

Units compiled with the same flags are first checked together, up to BATCH of them as one
translation unit that includes each (the Kokkos headers, most of every unit's time, are then
parsed once per batch: CI's clang.syntax took 317 s unit by unit, 147 s in batches of 8; in
batches of 32 with the programs' main files batched too, 43 batches became 24 and 92 s became
54 s alone on 2 cores). A program's main is renamed in its batch (#define main), so that two
programs can share one. A batch that fails is checked again unit by unit, and only a unit that
fails alone fails the test, so the verdict is the unit-by-unit one (a name two units of a batch
both define costs time, not a failure: keep such names apart).

Usage: clang_syntax.py BUILD_DIR SOURCE_DIR [-j N]
"""
import concurrent.futures
import json
import os
import re
import shlex
import shutil
import subprocess
import sys

WARNINGS = ["-Wall", "-Wextra", "-Wshadow", "-Werror"]
BATCH = 32
# GCC-only flags in the GCC build's command lines that Clang rejects or warns about.
DROP = {"-fno-fat-lto-objects"}


def clang_flags(entry):
    """The unit's compile flags without the compiler, its output and its own file name."""
    args = entry.get("arguments") or shlex.split(entry["command"])
    # The first word is the compiler, possibly behind a launcher (ccache).
    while args and os.path.basename(args[0]) in ("ccache", "sccache"):
        args = args[1:]
    out, skip = [], False
    for a in args[1:]:
        if skip:
            skip = False
            continue
        if a in ("-o", "-MF", "-MT", "-MQ"):
            skip = True
            continue
        if a in DROP or a in ("-c", "-MD", "-MMD", entry["file"]):
            continue
        out.append(a)
    return tuple(out)


def check(clang, flags, directory, source_file):
    r = subprocess.run([clang, *flags, source_file, "-fsyntax-only", *WARNINGS], cwd=directory,
                       capture_output=True, text=True)
    return r.returncode, r.stderr


def defines_main(path):
    with open(path, errors="replace") as f:
        return re.search(r"^int main\(", f.read(), re.M) is not None


def batches(units):
    """Units grouped by directory and flags, in groups of at most BATCH."""
    groups = {}
    for e in units:
        groups.setdefault((e["directory"], clang_flags(e)), []).append(e["file"])
    for (directory, flags), files in sorted(groups.items()):
        for i in range(0, len(files), BATCH):
            yield directory, flags, files[i:i + BATCH]


def batch_source(files):
    """One translation unit including each of `files`, each program's main renamed apart."""
    lines = []
    for k, path in enumerate(files):
        real = os.path.realpath(path)
        if defines_main(path):
            lines += [f"#define main rtmini_syntax_main_{k}\n", f'#include "{real}"\n', "#undef main\n"]
        else:
            lines.append(f'#include "{real}"\n')
    return lines


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

    batch_dir = os.path.join(os.path.realpath(build), "clang_syntax")
    os.makedirs(batch_dir, exist_ok=True)

    def check_batch(numbered):
        number, (directory, flags, files) = numbered
        if len(files) > 1:
            batch = os.path.join(batch_dir, f"batch_{number}.cpp")
            with open(batch, "w") as f:
                f.writelines(batch_source(files))
            code, err = check(clang, flags, directory, batch)
            if code == 0:
                return [], None
        failures = []
        for path in files:
            code, err_one = check(clang, flags, directory, path)
            if code != 0:
                failures.append((path, err_one))
        return failures, (err if len(files) > 1 else None)

    work = list(enumerate(batches(units)))
    failed = rechecked = 0
    with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
        for failures, batch_err in pool.map(check_batch, work):
            for path, err in failures:
                failed += 1
                print(f"FAIL {os.path.relpath(path, source)}\n{err}")
            if batch_err is not None and not failures:  # clean alone: a clash within the batch
                rechecked += 1
                print(f"NOTE a batch failed whose units are clean alone (rechecked one by one; "
                      f"rename the clash):\n{batch_err[:2000]}")
    print(f"{len(units) - failed} of {len(units)} translation units clean under clang++ "
          f"{' '.join(WARNINGS)} ({len(work)} batches, {rechecked} rechecked unit by unit)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
