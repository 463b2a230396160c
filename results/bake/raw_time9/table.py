#!/usr/bin/python3
"""Bake times of raw_time9/run.sh OUT: per binary every run's bake time (base + iterations, from
the log) and iterate phase, the median and the spread (max - min), and the verification hashes."""
import glob
import json
import os
import re
import statistics
import sys

out = sys.argv[1]
print("| binary | bake time per run (s) | median | spread | iterate phase median (s) | hashes |")
print("|---|---|---|---|---|---|")
for which in ("main", "new"):
    times, iterate, hashes = [], [], set()
    for path in sorted(glob.glob(os.path.join(out, which + "_*.json"))):
        s = json.load(open(path))
        log = open(path[:-5] + ".log").read()
        times.append(float(re.search(r"bake time ([0-9.]+) s", log).group(1)))
        iterate.append(s["phases"]["iterate"])
        hashes.add(s["verification_hash"])
    if times:
        print(f"| {which} | " + " / ".join(f"{t:.2f}" for t in times) +
              f" | {statistics.median(times):.2f} | {max(times) - min(times):.2f} | "
              f"{statistics.median(iterate):.2f} | {', '.join(sorted(hashes))} |")
