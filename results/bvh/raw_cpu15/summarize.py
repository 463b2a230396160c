#!/usr/bin/env python3
"""Summarises explore.sh's outputs: per mesh, workload and variant, the paired CPU-time ratio
rtmini/Embree (each run's median of 5 repeats), trace time, node/leaf stats, verification hash."""
import re, sys, glob, os, statistics
from collections import defaultdict
d = sys.argv[1]
rows = defaultdict(list)
for f in sorted(glob.glob(os.path.join(d, '*_run*.txt'))):
    m = re.match(r'(.+)_(ao|diffuse|shadow|primary)_(.+)_run(\d+)\.txt', os.path.basename(f))
    if not m: continue
    t = open(f).read()
    r = re.search(r'paired CPU time \(5 repeats\): speed ratio rtmini/embree median ([\d.]+)', t)
    tr = re.search(r'trace ([\d.]+) s \(best', t)
    h = re.search(r'verification ([0-9a-f]+)', t)
    st = re.search(r'per ray: ([\d.]+) nodes visited, ([\d.]+) triangle tests', t)
    wt = re.search(r'wide tree: (\d+) nodes, (\d+) leaves \(mean ([\d.]+) triangles, (\d+) compact\)', t)
    sb = re.search(r'sah build ([\d.]+) ms vs embree ([\d.]+) ms CPU', t)
    rows[(m.group(1), m.group(2), m.group(3))].append(
        (float(r.group(1)) if r else None, float(tr.group(1)) if tr else None, h.group(1) if h else '?',
         st.groups() if st else None, wt.groups() if wt else None, sb.groups() if sb else None))
print('| mesh | workload | variant | runs | CPU ratio median [min-max] | trace s median | nodes, tri tests /ray | wide nodes, leaves, mean, compact | rtmini build CPU ms median | verification |')
print('|---|---|---|---|---|---|---|---|---|---|')
for k in sorted(rows):
    v = rows[k]
    rs = [x[0] for x in v if x[0] is not None]; ts = [x[1] for x in v if x[1] is not None]
    hs = sorted(set(x[2] for x in v))
    bs = [float(x[5][0]) for x in v if x[5]]
    print(f'| {k[0]} | {k[1]} | {k[2]} | {len(v)} | {statistics.median(rs):.3f} [{min(rs):.3f}-{max(rs):.3f}] | '
          f'{statistics.median(ts):.4f} | {", ".join(v[0][3]) if v[0][3] else "?"} | {", ".join(v[0][4]) if v[0][4] else "?"} | '
          f'{statistics.median(bs) if bs else 0:.1f} | {" ".join(hs)} |')
