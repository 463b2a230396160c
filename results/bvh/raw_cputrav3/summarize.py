#!/usr/bin/env python3
"""Summarises run.sh: per mesh, workload and bench (main / branch), the median over the runs (and
the range) of each run's paired ratios against Embree (CPU time and wall), and the median over the
runs of branch / main of the CPU-time ratios of the same run index (the paired gain).
Usage: summarize.py [DIR]"""
import glob
import os
import re
import statistics
import sys

d = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
rows = {}
for f in sorted(glob.glob(os.path.join(d, "*_run*.txt"))):
    m = re.match(r"(.+)_(ao_small|shadow|primary|diffuse)_(main|branch)_run(\d+)\.txt",
                 os.path.basename(f))
    if not m:
        continue
    text = open(f).read()
    wall = re.search(r"paired \(\d+ repeats\): speed ratio rtmini/embree median ([\d.]+)", text)
    cpu = re.search(r"paired CPU time \(\d+ repeats\): speed ratio rtmini/embree median ([\d.]+)",
                    text)
    ver = re.search(r"verification ([0-9a-f]{16})", text)
    best = re.search(r"trace ([\d.]+) s \(best of", text)
    agree = re.search(r"agreement ([\d.]+)%", text)
    per_ray = re.search(r"per ray: ([\d.]+) nodes visited, ([\d.]+) triangle tests", text)
    loads = [float(x) for x in re.findall(r"load average: ([\d.]+)", text)]
    if not (wall and cpu and ver):
        print("incomplete:", f)
        continue
    rows.setdefault((m.group(1), m.group(2)), {}).setdefault(m.group(3), {})[int(m.group(4))] = dict(
        wall=float(wall.group(1)), cpu=float(cpu.group(1)), ver=ver.group(1),
        best=float(best.group(1)),
        agree=agree.group(1) if agree else "-", nodes=per_ray.group(1), tests=per_ray.group(2),
        loads=loads)


def med(xs):
    return "%.3f [%.3f-%.3f]" % (statistics.median(xs), min(xs), max(xs)) if xs else "-"


order = ["ao_small", "shadow", "primary", "diffuse"]
print("| mesh | workload | runs | branch: ratio (CPU) | main: ratio (CPU) | branch / main (CPU, "
      "paired by run) | rtmini trace time branch / main (best of 5, wall, paired by run) | branch: ratio (wall) | main: ratio (wall) | nodes / tests per ray "
      "(branch; main) | verification (both) | agreement | load avg |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for (mesh, w), byb in sorted(rows.items(), key=lambda kv: (kv[0][0], order.index(kv[0][1]))):
    b, a = byb.get("branch", {}), byb.get("main", {})
    runs = sorted(set(b) & set(a))
    vers = sorted(set(x["ver"] for x in list(b.values()) + list(a.values())))
    loads = [l for x in list(b.values()) + list(a.values()) for l in x["loads"]]
    first_b, first_a = b[runs[0]], a[runs[0]]
    print("| %s | %s | %d | %s | %s | %s | %s | %s | %s | %s / %s; %s / %s | %s | %s%% | %.1f-%.1f |" % (
        mesh, w, len(runs), med([b[i]["cpu"] for i in runs]), med([a[i]["cpu"] for i in runs]),
        med([b[i]["cpu"] / a[i]["cpu"] for i in runs]),
        med([b[i]["best"] / a[i]["best"] for i in runs]), med([b[i]["wall"] for i in runs]),
        med([a[i]["wall"] for i in runs]), first_b["nodes"], first_b["tests"], first_a["nodes"],
        first_a["tests"], " ".join("`%s`" % v for v in vers), first_b["agree"], min(loads),
        max(loads)))
