#!/usr/bin/env python3
"""Tables of results/bvh/slivers.md ("The auto split budget") from the raw output of
slivers_auto_measure.sh. Usage: slivers_auto_summary.py raw_auto/meshes_build.txt
raw_auto/meshes_primary.txt"""
import re
import statistics
import sys


def blocks(path):
    """One dict per run: label, mesh and the figures the bench printed."""
    out = []
    for chunk in open(path).read().split("### ")[1:]:
        head = chunk.splitlines()[0]
        b = {"label": head.split(":")[0], "mesh": head.split()[2].split("/")[-1]}
        pats = {
            "build_ms": r"build: sah ([\d.]+) ms",
            "sah": r"SAH cost ([\d.]+)",
            "fingerprint": r"tree fingerprint (\w+)",
            "nodes": r"per ray: ([\d.]+) nodes",
            "tests": r"nodes visited, ([\d.]+) triangle tests",
            "rate": r"traversal rate = ([\d.]+) Mrays/s",
            "hash": r"Mrays/s, verification (\w+)",
            "leaf": r"; (\d+) leaf triangles",
            "rss_kb": r"Maximum resident set size \(kbytes\): (\d+)",
        }
        for k, p in pats.items():
            m = re.search(p, chunk)
            if m:
                b[k] = m.group(1)
        if "leaf" in b:  # else the run failed (its output is kept in the raw file)
            out.append(b)
    return out


def med(values, digits=1):
    v = sorted(values)
    return f"{statistics.median(v):.{digits}f} [{v[0]:.{digits}f}, {v[-1]:.{digits}f}]"


def table(build_path, primary_path):
    runs = blocks(build_path)
    prim = blocks(primary_path)
    meshes = list(dict.fromkeys(b["mesh"] for b in runs))
    print("| mesh | side | leaf refs | SAH cost | tree fingerprint | runs | SAH build ms, median "
          "(best of 3 each) [min, max] | nodes / tests per ray | runs | Mrays/s median "
          "[min, max] | primary hash |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for mesh in meshes:
        for side in ("before", "after"):
            r = [b for b in runs if b["mesh"] == mesh and b["label"] == side]
            p = [b for b in prim if b["mesh"] == mesh and b["label"] == side]
            fps = sorted({b["fingerprint"] for b in r})
            hashes = sorted({b["hash"] for b in p})
            print(f"| {mesh} | {side} | {r[0]['leaf']} | {r[0]['sah']} | {' '.join(fps)} | "
                  f"{len(r)} | {med([float(b['build_ms']) for b in r])} | "
                  f"{p[0]['nodes']} / {p[0]['tests']} | {len(p)} | "
                  f"{med([float(b['rate']) for b in p], 3)} | {' '.join(hashes)} |")


if __name__ == "__main__":
    table(sys.argv[1], sys.argv[2])
