#!/usr/bin/env python3
"""Tabulates run_distributed.sh's `acceptance` runs (argument: its OUT_DIR): the issue's weak and
strong efficiency rows with repeats, each P-rank run paired with the 1-rank run of its own round
(the lent hosts drift by tens of percent within minutes, so a ratio of two medians taken minutes
apart says less than the median of ratios taken seconds apart). Bake time: base + map + halo +
iterate, as distributed_table.py; total: the whole run (read, set-up and write too)."""
import glob
import json
import os
import re
import statistics
import sys

from distributed_table import bake_time


def runs(out, pattern):
    """{name: (bake time, total, hash)} of the summaries matching the glob `pattern`."""
    found = {}
    for path in glob.glob(os.path.join(out, pattern)):
        s = json.load(open(path))
        p = s["phases"]
        found[os.path.basename(path)[:-5]] = (bake_time(p), p["total"], s["verification_hash"])
    return found


def spread(values, fmt="{:.3f}"):
    return (fmt.format(statistics.median(values)) + " [" + fmt.format(min(values)) + "-"
            + fmt.format(max(values)) + "]")


def weak(out):
    r = runs(out, "accweak_*.json")
    print("### Weak scaling: P rooms on P x 1 against 1 room on 1 x 1, --node-sharing on\n")
    print("| BVH | P | rounds | 1 x 1 bake (s) | P x 1 bake (s) | efficiency per round | median | "
          "by total time | P concurrent 1-room bakes: mean (s), of one alone | P x 1 against them |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    keys = {tuple(k.split("_")[1:4]) for k in r}
    for bvh, np in sorted({(b, int(p)) for b, p, _ in keys if p != "1"}):
        one, many, eff, eff_total = [], [], [], []
        for i in range(1, 10):
            a, b = r.get(f"accweak_{bvh}_1_{i}"), r.get(f"accweak_{bvh}_{np}_{i}")
            if not a or not b:
                continue
            one.append(a[0])
            many.append(b[0])
            eff.append(a[0] / b[0])
            eff_total.append(a[1] / b[1])
        if not eff:
            continue
        busy = [v[0] for v in runs(out, f"accbusy_{np}_*.json").values()]
        ceiling = against = "-"
        if busy and bvh == "lbvh":
            mean = statistics.mean(busy)
            ceiling = f"{mean:.3f}, {statistics.median(one) / mean:.0%}"
            against = f"{mean / statistics.median(many):.0%}"
        print(f"| {bvh} | {np} | {len(eff)} | {spread(one)} | {spread(many)} | "
              + ", ".join(f"{e:.0%}" for e in eff) + f" | **{statistics.median(eff):.0%}** | "
              f"{statistics.median(eff_total):.0%} | {ceiling} | {against} |")
    print(f"\nWeak hashes (one per P): {len({v[2] for v in r.values()})}")


def strong(out):
    r = runs(out, "accstrong_*.json")
    if not r:
        return
    print("\n### Strong scaling: bunny_room N = 300 K = 4\n")
    print("| ranks x threads | runs | bake time median [min-max] (s) | / 1 x 16 (per round) | "
          "efficiency against the 1 x 1 runs |")
    print("|---|---|---|---|---|")
    one = [v[0] for k, v in r.items() if k.startswith("accstrong_1x1_")]
    base = {k: v[0] for k, v in r.items() if k.startswith("accstrong_1x16_")}
    for pt in ("1x1", "1x16", "16x1"):
        t = {k: v[0] for k, v in r.items() if re.fullmatch(f"accstrong_{pt}_\\d+", k)}
        if not t:
            continue
        ratios = [v / base[k.replace(pt, "1x16")] for k, v in t.items()
                  if k.replace(pt, "1x16") in base]
        eff = [o / (16 * v) for o in one for v in t.values()] if pt != "1x1" else []
        print(f"| {pt.replace('x', ' x ')} | {len(t)} | {spread(list(t.values()))} | "
              + (spread(ratios) if pt != "1x1" else "-") + " | "
              + (spread(eff, "{:.0%}") if eff else "-") + " |")
    print(f"\nHashes: {sorted({v[2] for v in r.values()})}")


if __name__ == "__main__":
    weak(sys.argv[1])
    strong(sys.argv[1])
