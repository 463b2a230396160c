#!/usr/bin/env python3
"""The cost model of the bake's --balance cost, and what it predicts (results/bake/balance.md).

1. Fit: the per-rank times of the 16-core runs of commit e7c336d (raw_16core_fused/strong_e7c336d,
   cut by the pilot) against the work each rank did there, counted again here by `--balance
   pilot` runs of the same scene (the same cut: every rank's colour count is checked against the
   timings file). Mirror iterations that read the hit cache (2..K, median per rank) against
   colours and lookup hits; the mirror trace (phase map) against BVH nodes.
2. Predict: per-rank iteration and trace times of any run's counted work (summary scene.work)
   with the 16 x 1 fit, and their max / mean.

Usage: balance_fit.py RAW_DIR LOCAL_DIR  (LOCAL_DIR: pilot_P.json and cost_P.json summaries)"""
import json
import os
import sys

import h5py
import numpy as np

raw, local = sys.argv[1], sys.argv[2]


def counted(path):
    return json.load(open(path))["scene"]["work"]


def per_rank(w, k):
    return np.array(w[k]["per_rank"], dtype=float)


def fit(rows, cols, y):
    a = np.array([[r[c] for c in cols] for r in rows])
    b = np.array([r[y] for r in rows])
    coef = np.linalg.lstsq(a, b, rcond=None)[0]
    pred = a @ coef
    r2 = 1 - ((b - pred) ** 2).sum() / ((b - b.mean()) ** 2).sum()
    return coef, r2


rows = []
for ranks, threads in [(16, 1), (8, 2), (4, 4)]:
    path = os.path.join(local, f"pilot_{ranks}.json")
    if not os.path.exists(path):
        continue
    w = counted(path)
    h5 = h5py.File(os.path.join(raw, f"strong_{ranks}x{threads}.h5"), "r")
    items = per_rank(w, "items")
    assert (items == h5["ranks/work_units"][:] // 5).all(), "not the same cut"
    it = np.median(h5["iterations/trace_time"][:, 2:], axis=1) * threads
    ph = (h5["phases/end"][:] - h5["phases/start"][:])[:, 3] * threads  # phase "map"
    for r in range(ranks):
        rows.append({"cfg": f"{ranks}x{threads}", "items": items[r],
                     "lookups": per_rank(w, "lookups")[r], "remote": per_rank(w, "remote_reads")[r],
                     "nodes": per_rank(w, "trace_nodes")[r], "it": it[r], "map": ph[r]})

print("Fits (ns per unit; times x threads per rank):")
for cfgs in (["16x1"], ["16x1", "8x2"], ["16x1", "8x2", "4x4"]):
    sel = [r for r in rows if r["cfg"] in cfgs]
    if len(sel) < 4:
        continue
    for cols in (["items", "lookups"], ["items", "lookups", "remote"]):
        c, r2 = fit(sel, cols, "it")
        print(f"  {'+'.join(cfgs)}: cached iteration ~ {', '.join(f'{x * 1e9:.0f} {n}' for x, n in zip(c, cols))}"
              f" (r^2 {r2:.2f}, lookup / colour {c[1] / c[0]:.1f})")
    c, r2 = fit(sel, ["nodes"], "map")
    print(f"  {'+'.join(cfgs)}: mirror trace ~ {c[0] * 1e9:.1f} ns per BVH node (r^2 {r2:.2f})")

ns_item, ns_lookup, ns_node = 59e-9, 1459e-9, 39.5e-9  # the 16 x 1 fits, rounded
print("\nPredicted with the 16 x 1 fit (59 ns per colour + 1459 ns per lookup hit; 39.5 ns per node):")
print("| ranks | cut | cached iteration max / mean (s) | max / mean | mirror trace max / mean (s) | max / mean | hits moved |")
print("|---|---|---|---|---|---|---|")
for ranks in (2, 4, 8, 16):
    for cut in ("pilot", "cost"):
        path = os.path.join(local, f"{cut}_{ranks}.json")
        if not os.path.exists(path):
            continue
        w = counted(path)
        it = ns_item * per_rank(w, "items") + ns_lookup * per_rank(w, "lookups")
        tr = ns_node * per_rank(w, "trace_nodes")
        moved = per_rank(w, "moved_hits").sum() / per_rank(w, "items").sum()
        print(f"| {ranks} | {cut} | {it.max():.3f} / {it.mean():.3f} | {it.max() / it.mean():.3f} | "
              f"{tr.max():.3f} / {tr.mean():.3f} | {tr.max() / tr.mean():.3f} | {100 * moved:.1f} % |")
