#!/usr/bin/env python3
"""The cost model's weight of a lookup hit (kitchen.hpp's kLookupHitCost, in colours) for each
lookup, from a device call that cut bunny_room by the pilot with no node sharing
(raw_grid_lookup/call3_fit): per rank, the median of the cached iterations (2..K) x threads
against the colours and lookup hits the rank counted (its summary's scene.work), least squares
over 16 x 1 alone and over 16 x 1, 8 x 2 and 4 x 4 pooled; then what the cost cut's own run
(cut with the weight 25) would have been predicted to be under other weights.

Usage: lookup_weight_fit.py RAW_DIR (the call's folder, with runs.tgz)"""
import io
import json
import os
import sys
import tarfile

import h5py
import numpy as np


def load(tar, name):
    summary = json.load(tar.extractfile(f"runs/{name}.json"))["scene"]["work"]
    timings = h5py.File(io.BytesIO(tar.extractfile(f"runs/{name}.h5").read()), "r")
    items = np.array(summary["items"]["per_rank"], float)
    lookups = np.array(summary["lookups"]["per_rank"], float)
    return items, lookups, np.median(timings["iterations/trace_time"][:, 2:], axis=1)


def main(raw):
    with tarfile.open(os.path.join(raw, "runs.tgz")) as tar:
        for lookup in ("grid", "kdtree"):
            rows = []
            for shape in ("16x1", "8x2", "4x4"):
                threads = int(shape.split("x")[1])
                for rnd in (1, 2):
                    items, lookups, t = load(tar, f"pilot{shape}_{lookup}_{rnd}")
                    rows += [(shape, i, l, s * threads) for i, l, s in zip(items, lookups, t)]
            for shapes in (("16x1",), ("16x1", "8x2", "4x4")):
                sel = [r for r in rows if r[0] in shapes]
                a = np.array([[r[1], r[2]] for r in sel])
                b = np.array([r[3] for r in sel])
                c = np.linalg.lstsq(a, b, rcond=None)[0]
                r2 = 1 - ((b - a @ c) ** 2).sum() / ((b - b.mean()) ** 2).sum()
                print(f"{lookup}, {'+'.join(shapes)}: {c[0] * 1e9:.0f} ns per colour, "
                      f"{c[1] * 1e9:.0f} ns per lookup hit: weight {c[1] / c[0]:.1f} "
                      f"(r^2 {r2:.2f}, {len(sel)} ranks)")
            items, lookups, t = load(tar, f"cost16x1_{lookup}_1")
            predicted = ", ".join(f"{w}: {(items + w * lookups).max() / (items + w * lookups).mean():.3f}"
                                  for w in (2.5, 4, 10, 25))
            print(f"  cost cut (weight 25), 16 x 1: measured cached iteration max / mean "
                  f"{t.max() / t.mean():.3f}; its counted work's max / mean under weight {predicted}")


if __name__ == "__main__":
    main(sys.argv[1])
