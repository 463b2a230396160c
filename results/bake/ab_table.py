#!/usr/bin/env python3
"""Tabulates an A/B device call of bake (arguments: its folders, with times.txt and runs.tgz;
--variants NEW OLD names the two variants, default new old): runs named GROUP_VARIANT_ROUND
(e.g. w16_new_2) are grouped by GROUP and VARIANT; per group the median bake time and range of
each variant, the median of the per-round ratios new / old, and, where the timings files are
there (h5py), the median of the cached mirror iterations (2..K) of the slowest rank. Weak
efficiency: each round's w1 over its w16, per variant (its own w1 runs where the call ran them).
Strong scaling, where the call ran s1x1 of a variant: s1x1 / (16 x s1x16) and / (16 x s16x1) per
round, and s16x1 / s1x16."""
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


VARIANTS = ["new", "old"]


def split(name):
    m = re.match(r"(.+)_(" + "|".join(VARIANTS) + r")_(\d+)$", name)
    return (m.group(1), m.group(2), int(m.group(3))) if m else None


def table(folder):
    new_name, old_name = VARIANTS
    times, cached = bake_times(folder), cached_iterations(folder)
    runs = collections.defaultdict(dict)
    for name, t in times.items():
        key = split(name)
        if key:
            runs[(key[0], key[1])][key[2]] = (t, cached.get(name))
    print(f"{folder}\n")
    print(f"| runs | {new_name}: median (range) | {old_name}: median (range) |"
          f" {new_name} / {old_name}, median of rounds | cached iteration, {new_name} / {old_name} |")
    print("|---|---|---|---|---|")
    for group in sorted({g for g, _ in runs}):
        new, old = runs.get((group, new_name), {}), runs.get((group, old_name), {})
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
    for variant in VARIANTS:
        # Each variant against its own 1-room runs where the call ran them, else the new ones.
        one = runs.get(("w1", variant)) or runs.get(("w1", new_name))
        many = runs.get(("w16", variant))
        if one and many:
            eff = [one[i][0] / many[i][0] for i in sorted(set(one) & set(many))]
            print(f"\nweak efficiency, w1 / w16_{variant} per round: "
                  + ", ".join(f"{100 * e:.0f} %" for e in eff)
                  + f" (median {100 * statistics.median(eff):.0f} %)")
        serial = runs.get(("s1x1", variant), {})
        threads, ranks = runs.get(("s1x16", variant), {}), runs.get(("s16x1", variant), {})
        if serial and threads and ranks:
            t1 = statistics.median(t for t, _ in serial.values())
            rounds = sorted(set(threads) & set(ranks))
            def effs(r):
                return ", ".join(f"{100 * t1 / (16 * r[i][0]):.0f} %" for i in rounds)
            print(f"strong, {variant} (1 x 1 {t1:.2f} s): 1 x 16 {effs(threads)}; 16 x 1 "
                  f"{effs(ranks)}; 16 x 1 / 1 x 16 "
                  + ", ".join(f"{ranks[i][0] / threads[i][0]:.3f}" for i in rounds))


if __name__ == "__main__":
    args = sys.argv[1:]
    if args[:1] == ["--variants"]:
        VARIANTS[:] = args[1:3]
        args = args[3:]
    for folder in args:
        table(folder)
        print()
