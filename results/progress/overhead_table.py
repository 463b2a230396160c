#!/usr/bin/env python3
"""Render time per binary and progress mode from overhead.sh's output: the median, and the
progress cost as the median over iterations of (mode / none) of the same binary in the same
iteration (the runs of one iteration follow each other, so the pairing cancels slow drifts
of the shared machine's load). Usage: overhead_table.py FILE"""
import statistics
import sys
from collections import defaultdict

runs = defaultdict(list)
for line in open(sys.argv[1]):
    parts = line.split()
    if len(parts) == 3:
        runs[(parts[0], parts[1])].append(float(parts[2]))
print("| binary | mode | runs | median s | min-max s | cost vs none: median of paired ratios (min-max) |")
print("|---|---|---|---|---|---|")
for b in ("old", "new"):
    for mode in ("none", "log", "tty"):
        v = runs[(b, mode)]
        ratios = [x / y - 1 for x, y in zip(v, runs[(b, "none")])]
        cost = "" if mode == "none" else (f"{100 * statistics.median(ratios):+.1f} % "
                                          f"({100 * min(ratios):+.0f} to {100 * max(ratios):+.0f} %)")
        print(f"| {b} | {mode} | {len(v)} | {statistics.median(v):.3f} | "
              f"{min(v):.3f}-{max(v):.3f} | {cost} |")
