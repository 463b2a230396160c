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


def runs(out, pattern):
    """{name: (bake time, total, hash)} of the summaries matching the glob `pattern`."""
    found = {}
    for path in glob.glob(os.path.join(out, pattern)):
        s = json.load(open(path))
        p = s["phases"]
        bake = p.get("base", 0) + p.get("map", 0) + p.get("halo", 0) + p.get("iterate", 0)
        found[os.path.basename(path)[:-5]] = (bake, p["total"], s["verification_hash"])
    return found


def spread(values, fmt="{:.3f}"):
    return (fmt.format(statistics.median(values)) + " [" + fmt.format(min(values)) + "-"
            + fmt.format(max(values)) + "]")


def weak(out):
    r = runs(out, "accweak_*.json")
    print("### Weak scaling: 1 room on 1 x 1 against 16 rooms on 16 x 1, --node-sharing on\n")
    print("| BVH | rounds | 1 x 1 bake (s) | 16 x 1 bake (s) | efficiency per round | median | "
          "by total time | hashes |")
    print("|---|---|---|---|---|---|---|---|")
    for bvh in ("lbvh", "sah"):
        one, many, eff, eff_total, hashes = [], [], [], [], set()
        for i in range(1, 10):
            a, b = r.get(f"accweak_{bvh}_1_{i}"), r.get(f"accweak_{bvh}_16_{i}")
            if not a or not b:
                continue
            one.append(a[0])
            many.append(b[0])
            eff.append(a[0] / b[0])
            eff_total.append(a[1] / b[1])
            hashes |= {a[2], b[2]}
        if not eff:
            continue
        print(f"| {bvh} | {len(eff)} | {spread(one)} | {spread(many)} | "
              + ", ".join(f"{e:.0%}" for e in eff) + f" | **{statistics.median(eff):.0%}** | "
              f"{statistics.median(eff_total):.0%} | {len(hashes)} |")
    busy = [v[0] for v in runs(out, "accbusy_16_*.json").values()]
    if busy:
        alone = [v[0] for k, v in r.items() if k.startswith("accweak_lbvh_1_")]
        print(f"\n16 concurrent 1-room bakes (LBVH, no communication): bake time {spread(busy)} s "
              f"over {len(busy)}; mean {statistics.mean(busy):.3f} s, "
              f"{statistics.median(alone) / statistics.mean(busy):.0%} of one alone (median of "
              "the rounds').")


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
