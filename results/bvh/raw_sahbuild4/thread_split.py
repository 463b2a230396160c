#!/usr/bin/env python3
"""Summarises thread_split.txt (thread_split.sh): per mesh and bench, the median [min-max] over the
runs of the main thread's and the worker's perf samples, and the same as ms per SAH build (4 kHz
samples, 32 SAH builds per run: the bench's first build, the 30 timed ones and the SAH-cost one)."""
import os
import statistics
import sys

path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "thread_split.txt")
runs = {}
for line in open(path):
    f = line.split()
    runs.setdefault((f[0], f[1]), []).append((int(f[5]), int(f[6])))
print("| mesh | bench | runs | main thread samples | worker samples | main / worker ms per build |")
print("|---|---|---|---|---|---|")
for (mesh, bench), v in runs.items():
    main = [a for a, _ in v]
    worker = [b for _, b in v]
    ms = lambda s: statistics.median(s) * 0.25 / 32
    print(f"| {mesh} | {bench} | {len(v)} | {statistics.median(main):.0f} [{min(main)}-{max(main)}] | "
          f"{statistics.median(worker):.0f} [{min(worker)}-{max(worker)}] | {ms(main):.1f} / {ms(worker):.1f} |")
