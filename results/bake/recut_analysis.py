#!/usr/bin/env python3
"""What a recut by measured time could gain, from a run's timings file (run_distributed.sh's .h5):
per rank, the mirror trace's time per counted BVH node (phase `map`) and each mirror iteration's
time per counted iteration cost (scene.work.iteration_cost), both divided by their mean over the
ranks ("speed": 1 = the mean rank). If the cores differed, the trace's speeds would follow the
iterations'; if the counted cost misses work of some vertices, only the iterations' vary. Then the
slowest / mean of the cached iterations (2..K) if the ranges had been recut so that each rank's
counted cost times its speed in iteration 1 is equal, assuming each rank kept its cached speed.
Usage: recut_analysis.py RUN.h5 [...]"""
import json
import sys

import h5py
import numpy as np

for name in sys.argv[1:]:
    f = h5py.File(name, "r")
    work = json.loads(f.attrs["parameters"])["work"]
    per_rank = lambda k: np.array(work[k]["per_rank"], float)
    names = [n.decode() for n in f["phases/names"][:]]
    trace = (f["phases/end"][:] - f["phases/start"][:])[:, names.index("map")]
    it = f["iterations/trace_time"][:]
    cost = per_rank("iteration_cost")
    norm = lambda x: x / x.mean()
    trace_speed = norm(trace / per_rank("trace_nodes"))
    first = norm(it[:, 1] / cost)
    cached_time = it[:, 2:].mean(axis=1)
    cached = norm(cached_time / cost)
    print(f"{name}: {it.shape[0]} ranks")
    print("  trace time per node, by rank:       ", np.round(trace_speed, 2))
    print("  iteration 1 time per cost, by rank: ", np.round(first, 2))
    print("  cached iterations per cost, by rank:", np.round(cached, 2))
    print(f"  correlation with the cached iterations' time per cost: trace {np.corrcoef(trace_speed, cached)[0, 1]:.2f}, "
          f"iteration 1 {np.corrcoef(first, cached)[0, 1]:.2f}")
    now = cost * cached
    print(f"  cached iterations slowest / mean: {now.max() / now.mean():.3f} as run")
    for label, speed in (("trace", trace_speed), ("iteration 1", first)):
        share = (1 / speed) / (1 / speed).sum() * cost.sum()  # counted cost after the recut
        t = share * cached
        print(f"  recut by the {label}'s time per cost: {t.max() / t.mean():.3f} predicted")
