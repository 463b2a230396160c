#!/usr/bin/python3
"""Per-rank iteration times of the distributed bake (timings files, iterations/trace_time): per
run, the slowest rank's time in each iteration, that over the mean of the ranks, the slowest rank
of each cached iteration, the correlation of the ranks' relative times in iteration 1 with those
in iterations 2-4, the iterate phase, and (--balance measured) the recut's seconds and colours
moved. Arguments: timings files (.h5; the summary .json beside each)."""
import json
import sys

import h5py
import numpy as np

print("| run | slowest rank's time per iteration (s) | slowest / mean | slowest rank, iterations 1-4 "
      "| corr(it 1, it 2..4) | iterate (s) | recut (s) | colours moved |")
print("|---|---|---|---|---|---|---|---|")
for path in sys.argv[1:]:
    with h5py.File(path, "r") as h:
        t = h["iterations/trace_time"][...]
        names = [n.decode() if isinstance(n, bytes) else n for n in h["phases/names"][...]]
        phase = dict(zip(names, (h["phases/end"][...] - h["phases/start"][...]).max(axis=0)))
    recut = json.load(open(path[:-3] + ".json"))["scene"].get("recut", {})
    cached = t[:, 1:] / t[:, 1:].mean(axis=0)
    corr = [np.corrcoef(cached[:, 0], cached[:, k])[0, 1] for k in range(1, cached.shape[1])]
    fmt = lambda a, d: " ".join(f"{x:.{d}f}" for x in a)
    print(f"| {path.split('/')[-1][:-3]} | {fmt(t.max(axis=0), 3)} | {fmt(t.max(axis=0) / t.mean(axis=0), 2)} | "
          f"{' '.join(str(i) for i in t[:, 1:].argmax(axis=0))} | {fmt(corr, 2)} | {phase['iterate']:.3f} | "
          f"{recut.get('seconds', 0):.3f} | {recut.get('moved_colors', 0):.0f} |")
