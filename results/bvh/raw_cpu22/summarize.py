#!/usr/bin/env python3
"""Summarises the runs of run.sh: per mesh and workload, the median over the runs (and the range)
of each run's paired ratios (wall and CPU time), the SAH build ratios, the verification hashes
and the load. Usage: summarize.py [DIR]"""
import glob
import os
import re
import statistics
import sys

d = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
rows = {}
for f in sorted(glob.glob(os.path.join(d, "*_run*.txt"))):
    m = re.match(r"(.+)_(ao|ao_small|shadow|primary|diffuse)_run(\d+)\.txt", os.path.basename(f))
    if not m:
        continue
    text = open(f).read()
    wall = re.search(r"paired \(\d+ repeats\): speed ratio rtmini/embree median ([\d.]+).*?"
                     r"sah build median ([\d.]+) ms vs embree ([\d.]+) ms, time ratio median ([\d.]+)", text)
    cpu = re.search(r"paired CPU time \(\d+ repeats\): speed ratio rtmini/embree median ([\d.]+).*?"
                    r"sah build ([\d.]+) ms vs embree ([\d.]+) ms CPU, time ratio median ([\d.]+)", text)
    ver = re.search(r"verification ([0-9a-f]{16})", text)
    agree = re.search(r"agreement ([\d.]+)%", text)
    per_ray = re.search(r"per ray: ([\d.]+) nodes visited, ([\d.]+) triangle tests", text)
    loads = [float(x) for x in re.findall(r"load average: ([\d.]+)", text)]
    if not (wall and cpu and ver):
        print("incomplete:", f)
        continue
    r = rows.setdefault((m.group(1), m.group(2)), [])
    r.append(dict(wall=float(wall.group(1)), cpu=float(cpu.group(1)),
                  bwall=float(wall.group(4)), bcpu=float(cpu.group(4)),
                  sah_ms=float(cpu.group(2)), emb_ms=float(cpu.group(3)),
                  ver=ver.group(1), agree=agree.group(1) if agree else "-",
                  nodes=per_ray.group(1), tests=per_ray.group(2), loads=loads))


def med(xs):
    return "%.3f [%.3f-%.3f]" % (statistics.median(xs), min(xs), max(xs))


print("| mesh | workload | runs | ratio (CPU time) | ratio (wall) | SAH build time ratio (CPU) | "
      "SAH build time ratio (wall) | nodes / tests per ray | verification | agreement | load avg |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for (mesh, w), r in sorted(rows.items(), key=lambda kv: (kv[0][0], ["ao", "ao_small", "shadow", "primary", "diffuse"].index(kv[0][1]))):
    vers = sorted(set(x["ver"] for x in r))
    loads = [l for x in r for l in x["loads"]]
    print("| %s | %s | %d | %s | %s | %s | %s | %s / %s | %s | %s%% | %.1f-%.1f |" % (
        mesh, w, len(r), med([x["cpu"] for x in r]), med([x["wall"] for x in r]),
        med([x["bcpu"] for x in r]), med([x["bwall"] for x in r]), r[0]["nodes"], r[0]["tests"],
        " ".join("`%s`" % v for v in vers), r[0]["agree"], min(loads), max(loads)))
