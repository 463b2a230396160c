#!/usr/bin/env python3
"""Fails when a tracked file refers to a path outside the repository.

The repository must stand alone: a clone with nothing beside it builds, tests and runs. This
check reads every tracked text file and reports, one `file:line: reason` per finding:
  - a reference to the sibling reference folder (`..` + `/shared`),
  - an absolute path of a build machine (`/work/...`, `/root/...`, `/home/...`, or this
    checkout's own absolute path),
  - a relative path starting with `../` (scene files, mtllib lines, includes, links) or rooted at
    `${PROJECT_SOURCE_DIR}` that climbs out of the repository.
Measured results keep their provenance: files under results/ are checked only when they are
scripts (a figure's notes may say where it was measured; a script may not depend on it).

Usage: check_paths.py [REPO_ROOT]   (exit 0: clean, 1: findings listed on stdout)
"""
import os
import re
import subprocess
import sys

SCRIPT_SUFFIXES = (".sh", ".py", ".cmake", ".sbatch", ".qsub", ".mjs", ".js", "CMakeLists.txt")
# The patterns are assembled so that this file does not match itself.
SIBLING = re.compile(r"\.\./" + "shared" + r"\b")
MACHINE_ROOTS = re.compile(r"(?<![\w}).$/-])/(?:" + "work|root|home" + r")/[\w.-]")
RELATIVE = re.compile(r"""(?:^|(?<=[\s"'=(<\[,:]))((?:\.\./)+[^\s"'<>)\]\},;]*)""")
ROOTED = re.compile(r"\$\{(?:PROJECT_SOURCE_DIR|CMAKE_SOURCE_DIR|rtmini_SOURCE_DIR)\}((?:/\.\.)+)")


def tracked_files(root):
    """Paths relative to root: git's index when this is a checkout, else every file below root."""
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True,
                             capture_output=True).stdout
        return [p for p in out.decode().split("\0") if p]
    except (OSError, subprocess.CalledProcessError):
        skip = {".git", ".deps", "node_modules"}
        files = []
        for d, dirs, names in os.walk(root):
            dirs[:] = [x for x in dirs if x not in skip and not x.startswith("build")]
            files += [os.path.relpath(os.path.join(d, n), root) for n in names]
        return files


def is_checked(rel):
    """Everything except non-script files under results/ (provenance notes, raw logs)."""
    return not rel.startswith("results/") or rel.endswith(SCRIPT_SUFFIXES)


def read_text(path):
    """The file's text, or None for binary files (a NUL byte in the first 8 KiB)."""
    with open(path, "rb") as f:
        data = f.read()
    if b"\0" in data[:8192]:
        return None
    return data.decode("utf-8", errors="replace")


def escapes(root, rel, target):
    """True when the relative path `target`, read from the folder of `rel`, leaves root."""
    base = os.path.dirname(os.path.join(root, rel))
    resolved = os.path.normpath(os.path.join(base, target))
    return os.path.commonpath([os.path.normpath(root), resolved]) != os.path.normpath(root)


def findings_in(root, rel, text, own_paths):
    for number, line in enumerate(text.splitlines(), 1):
        where = f"{rel}:{number}"
        if SIBLING.search(line):
            yield f"{where}: refers to the sibling reference folder ({SIBLING.search(line).group(0)})"
        for own in own_paths:
            if own in line:
                yield f"{where}: contains this checkout's absolute path {own}"
        m = MACHINE_ROOTS.search(line)
        if m:
            yield f"{where}: absolute path of a build machine ({line[m.start():m.end() + 20].split()[0]})"
        for m in RELATIVE.finditer(line):
            if escapes(root, rel, m.group(1)):
                yield f"{where}: relative path {m.group(1)} leaves the repository"
        for m in ROOTED.finditer(line):
            yield f"{where}: path climbs above the source root ({m.group(0)})"


def main(argv):
    root = os.path.realpath(argv[1] if len(argv) > 1 else os.getcwd())
    own_paths = [root] if len(root) > 1 else []
    exempt = {"tests/repo/check_paths.py", "tests/repo/test_check_paths.py"}
    found = []
    for rel in tracked_files(root):
        path = os.path.join(root, rel)
        if rel in exempt or not is_checked(rel) or not os.path.isfile(path):
            continue
        text = read_text(path)
        if text is not None:
            found += findings_in(root, rel, text, own_paths)
    for f in found:
        print(f)
    print(f"check_paths: {len(found)} reference(s) outside {root}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
