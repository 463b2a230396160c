#!/usr/bin/python3
"""Issue 19, eighteenth round: where the 16 x 1 slowest rank comes from.

Reads the runs of raw_16core_noise/thp (16 x 1 with the default heap, with glibc's THP advice on
every mmap'd chunk, with the rank-to-core map reversed; 1 x 16) and prints, as Markdown:
per run, the ranks' mean cached iteration (iterations 2-4) over the run's mean, the slowest
ranks and each rank's heap on huge pages; then, over every 16 x 1 run (one deterministic cut),
how much of a rank's relative time is its own (the mean profile: work the cut mis-weighs) and
how much changes from run to run (the residual), and the correlation of the profile with each
counted work term. Usage: noise.py [DIR]   (DIR defaults to this script's thp/)."""
import glob
import json
import os
import sys

import h5py
import numpy as np

here = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "thp")
runs = sorted(glob.glob(os.path.join(here, "runs", "*.json")))
print("| run | bake time (s) | cached iteration mean / slowest (s) | slowest / mean | slowest ranks | heap on huge pages per rank (MiB) |")
print("|---|---|---|---|---|---|")
rel, names = [], []
for path in runs:
    s = json.load(open(path))
    name = os.path.basename(path)[:-5]
    t = h5py.File(path[:-5] + ".h5", "r")["iterations/trace_time"][:]
    huge = np.array(s["scene"]["resident_at_peak"]["rss_huge_after_step_bytes_per_rank"]) / 2**20
    cached = t[:, 2:].mean(axis=1)
    log = open(path[:-5] + ".log").read()
    bake = float(log.split("bake time ")[1].split()[0])  # the figure the bake prints
    if t.shape[0] > 1:
        rel.append(cached / cached.mean())
        names.append(name)
    print(f"| {name} | {bake:.3f} | {cached.mean():.3f} / {cached.max():.3f} | "
          f"{cached.max() / cached.mean():.3f} | {' '.join(map(str, np.argsort(-cached)[:3]))} | "
          f"{huge.min():.0f}-{huge.max():.0f} |")
rel = np.array(rel)
profile = rel.mean(axis=0)
residual = rel - profile
print()
print(f"16 x 1 runs: {len(rel)}; a rank's mean relative time over the runs (its own share of the "
      f"spread): std {profile.std():.3f}, largest {profile.max():.3f} (rank {profile.argmax()}); "
      f"run-to-run residual std {residual.std():.3f}; slowest/mean per run, mean "
      f"{rel.max(axis=1).mean():.3f} [{rel.max(axis=1).min():.3f}-{rel.max(axis=1).max():.3f}]")
work = json.load(open(runs[0]))["scene"]["work"]
terms = ["items", "lookups", "reads", "remote_reads", "trace_rays", "trace_nodes", "iteration_cost"]
print("correlation of the profile with counted work: " + ", ".join(
    f"{k} {np.corrcoef(profile, np.array(work[k]['per_rank']))[0, 1]:.2f}" for k in terms))
