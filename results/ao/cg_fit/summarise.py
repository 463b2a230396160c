#!/usr/bin/env python3
"""Median and range of the least-squares fit times in the run_host.sh summaries (ms)."""
import glob, json, os, re, statistics, sys
from collections import defaultdict

rows = defaultdict(list)
for path in sorted(glob.glob(os.path.join(sys.argv[1], "*.json"))):
    m = re.match(r"(.+)_t(\d)_(cholesky|cg)_rep\d+\.json", os.path.basename(path))
    s = json.load(open(path))
    lsq = s["scene"]["least_squares"]
    fit = 1e3 * (lsq["assemble_s"] + lsq["regularize_s"] + lsq["factor_s"] + lsq["solve_s"])
    rows[m.groups()].append((fit, 1e3 * lsq["solve_s"], lsq["cg_iterations"], s["verification_hash"]))
print("| scene | threads | fit | runs | fit ms, median [min-max] | of which solve ms | CG iterations | hash |")
print("|---|---|---|---|---|---|---|---|")
for (scene, threads, fit), v in sorted(rows.items()):
    f = [x[0] for x in v]
    s = [x[1] for x in v]
    print(f"| {scene} | {threads} | {fit} | {len(v)} | {statistics.median(f):.1f} [{min(f):.1f}-{max(f):.1f}] "
          f"| {statistics.median(s):.1f} | {v[0][2]} | `{','.join(sorted(set(x[3] for x in v)))}` |")
