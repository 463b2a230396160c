#!/usr/bin/env python3
"""Medians per mesh and setting from raw_sbvh/meshes_*.txt (sbvh_measure.sh), as markdown rows."""
import re, statistics, sys
from collections import defaultdict

runs = defaultdict(list)
cur = None
for line in open(sys.argv[1]):
    m = re.match(r"### .* (\S+) --workload .* --spatial-splits (\w+)", line)
    if m:
        cur = {"mesh": m.group(1).split("/")[-1], "sp": m.group(2)}
        continue
    if cur is None:
        continue
    if m := re.search(r"sah ([\d.]+) ms; traced with sah: SAH cost ([\d.]+)", line):
        cur["build"], cur["sah"] = float(m.group(1)), float(m.group(2))
    if m := re.search(r"; (\d+) leaf triangles \((\d+) input", line):
        cur["refs"], cur["tris"] = int(m.group(1)), int(m.group(2))
    if m := re.search(r"per ray: ([\d.]+) nodes visited, ([\d.]+) triangle tests", line):
        cur["nodes"], cur["tests"] = float(m.group(1)), float(m.group(2))
    if m := re.search(r"traversal rate = ([\d.e+-]+) Mrays/s, verification (\w+)", line):
        cur["rate"], cur["hash"] = float(m.group(1)), m.group(2)
        runs[(cur["mesh"], cur["sp"])].append(cur)
        cur = None

def med(v):
    return statistics.median(v), min(v), max(v)

print("| mesh | spatial | runs | leaf refs / tris | SAH cost | nodes/ray | tests/ray | SAH build ms median [min, max] | Mrays/s median [min, max] | hash |")
print("|---|---|---|---|---|---|---|---|---|---|")
for (mesh, sp), rs in runs.items():
    b, r = med([x["build"] for x in rs]), med([x["rate"] for x in rs])
    hashes = sorted({x["hash"] for x in rs})
    print(f"| {mesh} | {sp} | {len(rs)} | {rs[0]['refs']:,} / {rs[0]['tris']:,} | {rs[0]['sah']:.4g} | "
          f"{rs[0]['nodes']:.1f} | {rs[0]['tests']:.1f} | {b[0]:.1f} [{b[1]:.1f}, {b[2]:.1f}] | "
          f"{r[0]:.3f} [{r[1]:.3f}, {r[2]:.3f}] | {' '.join(hashes)} |")
