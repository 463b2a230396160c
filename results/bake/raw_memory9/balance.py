#!/usr/bin/python3
"""The counted balance and the locality of raw_memory8/run.sh's runs (argument: its OUT): per
binary and rank count, max / mean over ranks of the counted iteration cost, lookup hits and colour
entries (summary scene.work, deterministic), the ranges per rank (parameters.batches / ranks),
the most vertex ranges a rank owns (scene.map.ranges_per_rank, "-" where the summary has none), the fraction of mirror reads that are remote, the exchange's bytes per iteration (full; changed
runs send less) and the largest halo."""
import glob
import json
import os
import sys

out = sys.argv[1]
runs = []
for path in glob.glob(os.path.join(out, "*_*_*.json")):
    which, np, rep = os.path.basename(path)[:-5].split("_")
    runs.append((int(np), which, rep, json.load(open(path))))
print("| ranks | binary | iteration cost max/mean | lookups | items (colours) | ranges per rank "
      "| remote reads | exchange MiB/iteration | halo colours max | hash |")
print("|---|---|---|---|---|---|---|---|---|---|")
for np, which, rep, s in sorted(runs, key=lambda r: (r[0], r[1] != "main", r[2])):
    if np == 1:
        continue
    w, m = s["scene"]["work"], s["scene"]["map"]
    print(f"| {np} | {which} | {w['iteration_cost']['max_over_mean']:.3f} | "
          f"{w['lookups']['max_over_mean']:.3f} | {w['items']['max_over_mean']:.3f} | "
          f"{max(m['ranges_per_rank']) if 'ranges_per_rank' in m else '-'} | {m['remote_read_fraction']:.3f} | "
          f"{m['exchange_bytes_per_iteration'] / 2**20:.1f} | {m['halo_colors_max']:.0f} | "
          f"{s['verification_hash']} |")
