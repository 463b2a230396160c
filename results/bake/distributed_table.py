#!/usr/bin/env python3
"""Tabulates the summaries written by run_distributed.sh (argument: its OUT_DIR): bake time
(base + map + iterate), speed-up and efficiency against the first run of each group, peak RSS
per rank (max, min), the map each rank holds, remote-read fraction and exchange bytes."""
import glob
import json
import os
import sys


def rows(out, prefix):
    found = []
    for path in sorted(glob.glob(os.path.join(out, prefix + "_*.json"))):
        s = json.load(open(path))
        p = s["phases"]
        m = s["scene"].get("map", {})
        rss = s["scene"].get("peak_rss_bytes_per_rank", [s.get("peak_memory_bytes", 0)])
        found.append({
            "name": os.path.basename(path)[:-5], "ranks": s["ranks"], "threads": s["threads"],
            "time": p.get("base", 0) + p.get("map", 0) + p.get("halo", 0) + p.get("iterate", 0),
            "vertices": s["scene"]["vertices"], "colors": s["scene"]["colors"],
            "rss_max": max(rss) / 2**30, "rss_min": min(rss) / 2**30,
            "local": m.get("local_colors_max", 0), "remote": m.get("remote_read_fraction", 0),
            "bytes": m.get("exchange_bytes_per_iteration", 0), "hash": s["verification_hash"]})
    found.sort(key=lambda r: (r["ranks"] * r["threads"], r["ranks"]))
    return found


def table(title, found, weak):
    if not found:
        return
    print(f"\n### {title}\n")
    print("| run | ranks x threads | vertices | bake time (s) | speed-up | efficiency | peak RSS/rank "
          "max-min (GiB) | map/rank (% of whole) | remote reads | exchange MB/it | hash |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    t1 = found[0]["time"]
    for r in found:
        cores = r["ranks"] * r["threads"]
        speed = t1 / r["time"] if r["time"] > 0 else 0
        eff = speed if weak else speed / cores
        print(f"| {r['name']} | {r['ranks']} x {r['threads']} | {r['vertices']} | {r['time']:.3f} | "
              f"{'-' if weak else f'{speed:.2f}'} | {100 * eff:.0f} % | "
              f"{r['rss_max']:.3f}-{r['rss_min']:.3f} | {100 * r['local'] / r['colors']:.1f} | "
              f"{100 * r['remote']:.1f} % | {r['bytes'] / 1e6:.2f} | {r['hash']} |")


out = sys.argv[1]
table("Strong scaling (bunny_room, N=300, K=4)", rows(out, "strong"), False)
spatial = rows(out, "spatial")
if spatial:
    strong = rows(out, "strong")
    table("Strong scaling, --balance spatial (speed-up against strong_1x1)", strong[:1] + spatial, False)
table("Weak scaling (two sheets, side 150 sqrt(P), N=200, K=3)", rows(out, "weak"), True)
table("1M vertices, N=1000, K=2", rows(out, "big"), True)
