#!/usr/bin/env python3
"""Per-phase medians of `bake ao` logs: phase_medians.py DIR reads DIR/ao_<tag>_<rep>.log (the
phase lines "Load scene ...  70.62 ms" that bake ao prints, indented sub-phases included) and
prints, per phase, the median and range of each tag (base, new, then any other) over its
repetitions, and the verification hashes."""
import glob
import re
import statistics
import sys

phases, hashes = {}, {}
for path in sorted(glob.glob(sys.argv[1] + "/ao_*_*.log")):
    tag = path.rsplit("/", 1)[1].split("_")[1]
    for line in open(path):
        m = re.match(r"^\s*(\S.*?) \.\.\.\s+([0-9.]+) ms", line)
        if m:
            phases.setdefault(m.group(1), {}).setdefault(tag, []).append(float(m.group(2)))
        h = re.search(r"verification ([0-9a-f]+)", line)
        if h:
            hashes.setdefault(tag, set()).add(h.group(1))
seen = {t for by in phases.values() for t in by}
tags = [t for t in ("base", "new") if t in seen] + sorted(seen - {"base", "new"})
print(f"{'phase (ms)':28s}" + "".join(f"{t + ' median (min-max), n':>34s}" for t in tags))
for name, by in phases.items():
    cells = []
    for t in tags:
        v = by.get(t, [])
        cells.append(f"{statistics.median(v):.2f} ({min(v):.2f}-{max(v):.2f}), {len(v)}" if v else "-")
    print(f"{name:28s}" + "".join(f"{c:>34s}" for c in cells))
for t in tags:
    print(f"verification hashes {t}: {' '.join(sorted(hashes.get(t, [])))}")
