#!/usr/bin/env python3
"""The SAH build time ratio rtmini/Embree (CPU time, each run's median over its paired repeats)
that run.sh's runs printed, per mesh and bench (main / branch): median [min-max] over all runs
of all workloads, and rtmini's build CPU ms. Usage: build_ratios.py DIR"""
import glob
import os
import re
import statistics
import sys

d = sys.argv[1]
rows = {}
for f in sorted(glob.glob(os.path.join(d, "*_run*.txt"))):
    m = re.match(r"(.+)_(ao_small|shadow|primary|diffuse)_(main|branch)_run(\d+)\.txt",
                 os.path.basename(f))
    b = re.search(r"paired CPU time .*sah build ([\d.]+) ms vs embree ([\d.]+) ms CPU, time ratio "
                  r"median ([\d.]+)", open(f).read())
    if m and b:
        rows.setdefault((m.group(1), m.group(3)), []).append(
            (float(b.group(3)), float(b.group(1)), float(b.group(2))))
print("| mesh | bench | runs | SAH build time ratio rtmini/Embree (CPU) | rtmini ms | Embree ms |")
print("|---|---|---|---|---|---|")
for (mesh, bench), xs in sorted(rows.items()):
    r = [x[0] for x in xs]
    print("| %s | %s | %d | %.3f [%.3f-%.3f] | %.1f | %.1f |" % (
        mesh, bench, len(xs), statistics.median(r), min(r), max(r),
        statistics.median(x[1] for x in xs), statistics.median(x[2] for x in xs)))
