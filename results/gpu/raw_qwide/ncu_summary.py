#!/usr/bin/env python3
"""The two longest kernels of an `ncu --csv --metrics ...` log (the bench's timed trace and its
untimed stats pass), one line per metric. Usage: ncu_summary.py ncu_new.csv"""
import collections
import csv
import sys

rows = list(csv.reader(line for line in open(sys.argv[1]) if line.startswith('"')))
header, rows = rows[0], rows[1:]
kernels = collections.OrderedDict()
for r in rows:
    d = dict(zip(header, r))
    k = kernels.setdefault(d["ID"], {"kernel": d["Kernel Name"][:110], "grid": d["Grid Size"],
                                     "block": d["Block Size"]})
    k[d["Metric Name"]] = d["Metric Value"]
longest = sorted(kernels.values(),
                 key=lambda k: -float(k.get("gpu__time_duration.sum", "0").replace(",", "")))
for k in longest[:2]:
    for name, value in k.items():
        print(f"{name:60s} {value}")
    print()
