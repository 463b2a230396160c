#!/usr/bin/python3
"""Pairwise exchanges against MPI_Ialltoallv in one call (seventeenth round): per exchange and
shape, the median bake time, its ratio to the same binary's 1 x 16, the largest rank's peak RSS
and the issue's bound (1.2/P x the 1 x 16 map part + the run's scene RSS), in MiB. Argument: the
folder of {a2a,pair}_PxT_I.json."""
import glob
import json
import os
import re
import sys

M = 2**20
med = lambda x: sorted(x)[len(x) // 2]
runs = {}
for path in glob.glob(os.path.join(sys.argv[1], "*.json")):
    m = re.fullmatch(r"(a2a|pair)_(\d+)x(\d+)_\d", os.path.basename(path)[:-5])
    if not m:
        continue
    s = json.load(open(path))
    sc = s["scene"]
    peak = max(sc["peak_rss_bytes_per_rank"]) / M
    scene = max(sc["scene_rss_bytes_per_rank"]) / M
    bake = float(re.search(r"bake time ([0-9.]+) s", open(path[:-5] + ".log").read()).group(1))
    runs.setdefault((m.group(1), int(m.group(2)), int(m.group(3))), []).append(
        (bake, peak, scene, s["verification_hash"]))
print("| exchange | ranks x threads | runs | bake time median [min-max] (s) | vs 1 x 16 | "
      "peak RSS/rank max, median (MiB) | bound (MiB) | peak / bound | hashes |")
print("|---|---|---|---|---|---|---|---|---|")
for ex in ("a2a", "pair"):
    one = runs[(ex, 1, 16)]
    t16 = med([r[0] for r in one])
    map1 = med([r[1] - r[2] for r in one])
    for (e, p, t) in sorted(k for k in runs if k[0] == ex):
        r = runs[(e, p, t)]
        times = [x[0] for x in r]
        peak = med([x[1] for x in r])
        bound = 1.2 / p * map1 + med([x[2] for x in r])
        print(f"| {ex} | {p} x {t} | {len(r)} | {med(times):.3f} [{min(times):.3f}-{max(times):.3f}] | "
              f"{med(times) / t16:.2f} | {peak:.1f} | {bound:.1f} | {peak / bound:.3f} | "
              f"{' '.join(sorted(set(x[3] for x in r)))} |")
