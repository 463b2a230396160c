#!/usr/bin/env python3
"""Summarises build_*.txt (written by results/bvh/sahbuild_measure.sh) in this folder or the one
given as the first argument: per file and bench binary, the median over the runs [min-max] of each
run's paired median SAH build time ratio rtmini/Embree (wall and CPU time) and of the two build
times, plus the load averages seen. Reads the traced runs' lines and --build-only's paired line."""
import glob
import os
import re
import statistics
import sys

here = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
wall_re = re.compile(r"sah build median ([0-9.]+) ms vs embree ([0-9.]+) ms, time ratio median ([0-9.]+)")
cpu_re = re.compile(r"sah build ([0-9.]+) ms vs embree ([0-9.]+) ms CPU, time ratio median ([0-9.]+)")
paired_re = re.compile(r"paired builds .*: sah ([0-9.]+) ms vs embree ([0-9.]+) ms wall, ratio median ([0-9.]+) "
                       r".*; ([0-9.]+) ms vs ([0-9.]+) ms CPU, ratio median ([0-9.]+)")
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
        elif bench and (m := paired_re.search(line)):
            for key, group in (("ms", 1), ("ems", 2), ("wall", 3), ("cms", 4), ("cems", 5), ("cpu", 6)):
                runs[bench][key].append(float(m.group(group)))
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
