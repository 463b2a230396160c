#!/usr/bin/env python3
"""Tabulates run_local.sh's OUT_DIR: per run the bake time, hash, remote reads, the exchange's
bytes per iteration (timings: iterations/allgather_bytes, summed over ranks), its time, the
changed fraction and each rank's iteration times."""
import glob
import json
import os
import sys

import h5py
import numpy as np

out = sys.argv[1]
print("| run | ranks | vertices | bake time (s) | hash | remote reads | halo colours/it (full, MB) | "
      "bytes sent per exchange, summed over ranks (MB) | changed fraction | exchange time per it "
      "(max over ranks, s) | iteration time per rank (s) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for path in sorted(glob.glob(os.path.join(out, "*.json"))):
    s = json.load(open(path))
    p, m = s["phases"], s["scene"].get("map", {})
    t = p.get("base", 0) + p.get("map", 0) + p.get("halo", 0) + p.get("iterate", 0)
    h = h5py.File(path[:-5] + ".h5", "r")
    b = h["iterations/allgather_bytes"][:]  # ranks x iterations
    ex = h["iterations/allgather_time"][:] if "iterations/allgather_time" in h else None
    tr = h["iterations/trace_time"][:]
    sent = " / ".join(f"{x / 1e6:.3f}" for x in b.sum(axis=0))
    ext = " / ".join(f"{x:.3f}" for x in ex.max(axis=0)) if ex is not None else "-"
    per_rank = "; ".join(" ".join(f"{x:.2f}" for x in row) for row in tr)
    print(f"| {os.path.basename(path)[:-5]} | {s['ranks']} | {s['scene']['vertices']} | {t:.2f} | "
          f"{s['verification_hash']} | {100 * m.get('remote_read_fraction', 0):.2f} % | "
          f"{m.get('exchange_bytes_per_iteration', 0) / 1e6:.3f} | {sent} | "
          f"{m.get('exchange_changed_fraction', float('nan')):.3f} | {ext} | {per_rank} |")
