#!/usr/bin/env python3
"""Pairs the runs of raw_sahbuild/meshes.txt (BEFORE then AFTER per mesh and workload) and prints,
for each, the SAH cost, nodes/tests per ray, verification hash and rate of both, and whether the
tree statistics and the hash agree."""
import os
import re

here = os.path.dirname(os.path.abspath(__file__))
runs = []
for line in open(os.path.join(here, "meshes.txt")):
    if line.startswith("### "):
        parts = line.split()
        mesh = os.path.basename(parts[2])
        w = parts[parts.index("--workload") + 1]
        runs.append({"bench": os.path.basename(parts[1]), "mesh": mesh, "workload": w})
    elif runs and (m := re.search(r"SAH cost ([0-9.]+)", line)):
        runs[-1]["sah"] = m.group(1)
    elif runs and (m := re.search(r"per ray: ([0-9.]+) nodes visited, ([0-9.]+) triangle tests", line)):
        runs[-1]["nt"] = f"{m.group(1)} / {m.group(2)}"
    elif runs and (m := re.search(r"FOM ([0-9.]+) Mrays/s .* verification ([0-9a-f]+)", line)):
        runs[-1]["rate"], runs[-1]["hash"] = m.group(1), m.group(2)
print("| mesh | workload | SAH cost | nodes / tests per ray | verification | rate main -> branch (Mrays/s) | same |")
print("|---|---|---|---|---|---|---|")
by_key = {}
for r in runs:
    by_key.setdefault((r["mesh"], r["workload"]), []).append(r)
for (mesh, w), rs in by_key.items():
    if len(rs) != 2 or not all("hash" in r for r in rs):
        continue
    a, b = rs
    same = all(a.get(k) == b.get(k) for k in ("sah", "nt", "hash"))
    print(f"| {mesh} | {w} | {b.get('sah')} | {b.get('nt')} | `{b['hash']}` | {a['rate']} -> {b['rate']} | {'yes' if same else 'NO'} |")
