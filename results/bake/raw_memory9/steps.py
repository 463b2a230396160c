#!/usr/bin/python3
"""Peak RSS after each step of the largest rank (summary scene.peak_rss_after_bytes_per_rank), with
what each step added, and that rank's own colours (C, work.items), halo colours (H) and colours
sent (S) where the summary has them. Arguments: summaries (.json)."""
import json
import os
import sys

STEPS = ["trace", "halo layout", "exchange plan", ""]


def order(k):
    if k in ("setup", "map", "halo"):
        return (0, ("setup", "map", "halo").index(k), 0)
    if k.startswith("iteration"):
        w = k.split()
        return (1, int(w[1]), STEPS.index(" ".join(w[2:])))
    return (2, 0, 0)


for path in sys.argv[1:]:
    s = json.load(open(path))["scene"]
    rss = s["peak_rss_bytes_per_rank"]
    r = rss.index(max(rss))
    m = s.get("map", {})
    extra = lambda k: f"{m[k][r]:.0f}" if k in m else "-"
    print(f"\n{os.path.basename(path)}: rank {r} of {len(rss)}, C = {s['work']['items']['per_rank'][r]:.0f}, "
          f"H = {extra('halo_colors_per_rank')}, S = {extra('send_colors_per_rank')}, "
          f"ranges {extra('ranges_per_rank')}\n")
    print("| step | peak RSS after (GiB) | added (MB) |")
    print("|---|---|---|")
    before = 0
    for k in sorted(s["peak_rss_after_bytes_per_rank"], key=order):
        v = s["peak_rss_after_bytes_per_rank"][k][r]
        print(f"| {k} | {v / 2**30:.4f} | {(v - before) / 1e6:+.2f} |")
        before = v
