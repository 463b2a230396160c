#!/usr/bin/env python3
"""Peak RSS per rank from run.sh's summaries (argument: its OUT): per binary and rank count the
largest and mean peak over ranks, the scene part (peak before any map), the issue's bound
1.2 / P x (1-rank peak - its scene) + scene computed with that binary's own 1-rank run, the ratio
peak / bound, the step that set the largest rank's peak, and the verification hash."""
import glob
import json
import os
import sys

# Marks within iteration N come as "iteration N trace", "iteration N halo layout", "iteration N
# exchange plan" (the fused first iteration's halo and exchange plan), then "iteration N".
ITERATION_STEPS = ["trace", "halo layout", "exchange plan", ""]


def iteration_step(k):
    words = k.split()
    return int(words[1]), ITERATION_STEPS.index(" ".join(words[2:]))


G = 2**30
out = sys.argv[1]
runs = {}
for path in glob.glob(os.path.join(out, "*_*_*.json")):
    which, np, rep = os.path.basename(path)[:-5].split("_")
    runs.setdefault((which, int(np)), []).append(json.load(open(path)))
print("| binary | ranks | peak RSS/rank max (GiB) | mean | scene | bound 1.2/P (GiB) | max / bound "
      "| peak set by (largest rank) | items max/mean | counted cost max/mean | halo colours max | hash |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for which in ("main", "new"):
    one = runs.get((which, 1))
    if not one:
        continue
    map1 = max(one[0]["scene"]["peak_rss_bytes_per_rank"]) - max(one[0]["scene"]["scene_rss_bytes_per_rank"])
    for np in sorted(p for w, p in runs if w == which):
        for s in runs[(which, np)]:
            sc = s["scene"]
            peak = sc["peak_rss_bytes_per_rank"]
            scene = max(sc["scene_rss_bytes_per_rank"])
            bound = 1.2 / np * map1 + scene
            steps = sc.get("peak_rss_after_bytes_per_rank")
            setby = "-"
            if steps:
                r = peak.index(max(peak))
                order = ["setup", "map", "halo"] + sorted(
                    (k for k in steps if k.startswith("iteration")), key=iteration_step) + ["write"]
                setby = next(k for k in order if k in steps and steps[k][r] >= max(peak) - 1)
            items = sc.get("work", {}).get("items", {}).get("max_over_mean", 1.0)
            cost = sc.get("work", {}).get("iteration_cost", {}).get("max_over_mean", 1.0)
            halo = sc.get("map", {}).get("halo_colors_max", "-")
            print(f"| {which} | {np} | {max(peak) / G:.3f} | {sum(peak) / len(peak) / G:.3f} | {scene / G:.3f} | "
                  f"{bound / G:.3f} | {max(peak) / bound:.2f} | {setby} | {items:.2f} | {cost:.3f} | "
                  f"{halo if halo == '-' else f'{halo:.0f}'} | {s['verification_hash']} |")
