#!/usr/bin/python3
"""What the largest rank held at its peak (summary scene.resident_at_peak, fifteenth round): the
step after which its peak was highest, that peak, the RSS the step left, the scene's RSS once
set up (the bound's replicated part) and the bake's buffers then, in MiB. Where the summary has
the resident set by kind (seventeenth round on), also the shared-memory pages after set-up and
after the peak's step (the bake maps none: the MPI library's) and the rest less their growth.
Arguments: summaries."""
import json
import os
import sys

M = 2**20
BUFFERS = ["map", "hits", "halo", "send_list", "exchange_scratch", "layout_tables",
           "first_iteration_reads", "per_vertex"]
print("| run | rank | step | peak | left resident | scene (setup peak / left) | "
      + " | ".join(BUFFERS) + " | rest | shared memory (setup / step) | rest less its growth |")
print("|---|---|---|---|---|---|" + "---|" * (len(BUFFERS) + 3))
for path in sys.argv[1:]:
    s = json.load(open(path))["scene"]
    rap = s.get("resident_at_peak")
    if not rap:
        continue
    peaks = rap["peak_bytes_per_rank"]
    r = peaks.index(max(peaks))
    scene_left = s["rss_after_bytes_per_rank"]["setup"][r]
    held = [rap[b][r] for b in BUFFERS]
    rest = rap["rss_after_step_bytes_per_rank"][r] - scene_left - sum(held)
    shm = "-", "-"
    if "rss_shmem_after_step_bytes_per_rank" in rap:
        before = s["rss_shmem_after_bytes_per_rank"]["setup"][r]
        after = rap["rss_shmem_after_step_bytes_per_rank"][r]
        shm = f"{before / M:.2f} / {after / M:.2f}", f"{(rest - (after - before)) / M:.2f}"
    print(f"| {os.path.basename(path)[:-5]} | {r} | {rap['step_per_rank'][r]} | {peaks[r] / M:.1f} | "
          f"{rap['rss_after_step_bytes_per_rank'][r] / M:.1f} | "
          f"{s['scene_rss_bytes_per_rank'][r] / M:.1f} / {scene_left / M:.1f} | "
          + " | ".join(f"{h / M:.2f}" for h in held) + f" | {rest / M:.2f} | {shm[0]} | {shm[1]} |")
