#!/usr/bin/env python3
"""Tabulates an A/B device call of bake (argument: its folder, with times.txt and runs.tgz):
runs named GROUP_VARIANT_ROUND (e.g. w16_new_2) are grouped by GROUP and VARIANT; per group the
median bake time and range of each variant, the median of the per-round ratios new / old, and,
where the timings files are there (h5py), the median of the cached mirror iterations (2..K) of
the slowest rank. Weak efficiency: each round's w1_new over its w16_new (and w1 over w16_old
when the call ran w1_old too)."""
import collections
import io
import os
import re
import statistics
import sys
import tarfile


def bake_times(folder):
    times = {}
    for line in open(os.path.join(folder, "times.txt")):
        m = re.match(r"(\S+) bake time ([0-9.]+) s", line)
        if m:
            times[m.group(1)] = float(m.group(2))
    return times


def cached_iterations(folder):
    """Per run: the median over iterations 2..K of the slowest rank's trace time."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        return {}
    out = {}
    with tarfile.open(os.path.join(folder, "runs.tgz")) as tar:
        for m in tar.getmembers():
            if m.name.endswith(".h5"):
                t = h5py.File(io.BytesIO(tar.extractfile(m).read()), "r")["iterations/trace_time"][:]
                if t.shape[1] > 2:
                    out[os.path.basename(m.name)[:-3]] = float(np.median(t.max(axis=0)[2:]))
    return out


def split(name):
    m = re.match(r"(.+)_(new|old)_(\d+)$", name)
    return (m.group(1), m.group(2), int(m.group(3))) if m else None


def table(folder):
    times, cached = bake_times(folder), cached_iterations(folder)
    runs = collections.defaultdict(dict)
    for name, t in times.items():
        key = split(name)
        if key:
            runs[(key[0], key[1])][key[2]] = (t, cached.get(name))
    print(f"{folder}\n")
    print("| runs | new: median (range) | old: median (range) | new / old, median of rounds |"
          " cached iteration, new / old |")
    print("|---|---|---|---|---|")
    for group in sorted({g for g, _ in runs}):
        new, old = runs.get((group, "new"), {}), runs.get((group, "old"), {})
        def summary(r):
            if not r:
                return "-"
            v = [t for t, _ in r.values()]
            return f"{statistics.median(v):.4f} ({min(v):.4f}-{max(v):.4f})"
        rounds = sorted(set(new) & set(old))
        ratio = (f"{statistics.median([new[i][0] / old[i][0] for i in rounds]):.3f}"
                 if rounds else "-")
        def iters(r):
            v = [c for _, c in r.values() if c is not None]
            return f"{statistics.median(v):.2f}" if v else "-"
        print(f"| {group} | {summary(new)} | {summary(old)} | {ratio} | {iters(new)} / {iters(old)} |")
    for variant in ("new", "old"):
        # Each variant against its own 1-room runs where the call ran them, else the new ones.
        one = runs.get(("w1", variant)) or runs.get(("w1", "new"))
        many = runs.get(("w16", variant))
        if one and many:
            eff = [one[i][0] / many[i][0] for i in sorted(set(one) & set(many))]
            print(f"\nweak efficiency, w1 / w16_{variant} per round: "
                  + ", ".join(f"{100 * e:.0f} %" for e in eff)
                  + f" (median {100 * statistics.median(eff):.0f} %)")


if __name__ == "__main__":
    for folder in sys.argv[1:]:
        table(folder)
        print()
