#!/usr/bin/env python3
"""Summarises raw_sahbuild/build_*.txt (written by results/bvh/sahbuild_measure.sh): per file and
bench binary, the median over the runs [min-max] of each run's paired median SAH build time ratio
rtmini/Embree (wall and CPU time) and of the two build times, plus the load averages seen."""
import glob
import os
import re
import statistics

here = os.path.dirname(os.path.abspath(__file__))
wall_re = re.compile(r"sah build median ([0-9.]+) ms vs embree ([0-9.]+) ms, time ratio median ([0-9.]+)")
cpu_re = re.compile(r"sah build ([0-9.]+) ms vs embree ([0-9.]+) ms CPU, time ratio median ([0-9.]+)")
load_re = re.compile(r"load average: ([0-9.]+)")


def fmt(v):
    return f"{statistics.median(v):.3f} [{min(v):.3f}-{max(v):.3f}]"


def fmt_ms(v):
    return f"{statistics.median(v):.1f}"


for path in sorted(glob.glob(os.path.join(here, "build_*.txt"))):
    runs = {}
    bench = None
    for line in open(path):
        if line.startswith("### "):
            bench = os.path.basename(line.split()[1])
            runs.setdefault(bench, {"wall": [], "cpu": [], "ms": [], "ems": [], "cms": [], "cems": [], "load": []})
        elif bench and (m := load_re.search(line)):
            runs[bench]["load"].append(float(m.group(1)))
        elif bench and (m := wall_re.search(line)):
            runs[bench]["ms"].append(float(m.group(1)))
            runs[bench]["ems"].append(float(m.group(2)))
            runs[bench]["wall"].append(float(m.group(3)))
        elif bench and (m := cpu_re.search(line)):
            runs[bench]["cms"].append(float(m.group(1)))
            runs[bench]["cems"].append(float(m.group(2)))
            runs[bench]["cpu"].append(float(m.group(3)))
    print(f"## {os.path.basename(path)}")
    print("| bench | runs | ratio CPU time | ratio wall | rtmini / Embree CPU ms | rtmini / Embree wall ms | load avg |")
    print("|---|---|---|---|---|---|---|")
    for bench, r in runs.items():
        if not r["cpu"]:
            continue
        print(f"| {bench} | {len(r['cpu'])} | {fmt(r['cpu'])} | {fmt(r['wall'])} | "
              f"{fmt_ms(r['cms'])} / {fmt_ms(r['cems'])} | {fmt_ms(r['ms'])} / {fmt_ms(r['ems'])} | "
              f"{min(r['load']):.1f}-{max(r['load']):.1f} |")
    print()
