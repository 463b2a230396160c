#!/usr/bin/env python3
"""Every registered test has an Open MPI temporary directory of its own
(rtmini_give_tests_own_mpi_tmpdir in tests/CMakeLists.txt), and no two share one: a directory
that adds tests without calling it brings back the isolated singletons' session-directory race.

Usage: check_mpi_tmpdirs.py CTEST BUILD_DIR
"""
import json
import subprocess
import sys

KEY = "OMPI_MCA_orte_tmpdir_base="


def tmpdir_of(test):
    for prop in test.get("properties", []):
        if prop["name"] == "ENVIRONMENT":
            for value in prop["value"]:
                if value.startswith(KEY):
                    return value[len(KEY):]
    return None


def main():
    ctest, build = sys.argv[1], sys.argv[2]
    listing = subprocess.run([ctest, "--show-only=json-v1"], cwd=build, check=True,
                             capture_output=True, text=True).stdout
    tests = json.loads(listing)["tests"]
    missing = [t["name"] for t in tests if tmpdir_of(t) is None]
    dirs = [tmpdir_of(t) for t in tests if tmpdir_of(t) is not None]
    shared = sorted({d for d in dirs if dirs.count(d) > 1})
    for name in missing:
        print(f"FAIL {name}: no {KEY[:-1]} (call rtmini_give_tests_own_mpi_tmpdir() at the end "
              f"of the CMakeLists.txt that adds it)")
    for d in shared:
        print(f"FAIL several tests share {d}")
    print(f"{len(tests) - len(missing)} of {len(tests)} tests have their own Open MPI temporary "
          f"directory")
    return 1 if missing or shared else 0


if __name__ == "__main__":
    sys.exit(main())
