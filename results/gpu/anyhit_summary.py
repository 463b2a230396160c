#!/usr/bin/env python3
"""Tables of anyhit_device.sh's output (issue 21).

  anyhit_summary.py bench bench.txt       one line per mesh, build and kernel: the best Grays/s of
                                          its runs, the ratio to `default`, the hash (and whether
                                          every run of the mesh gave the default's)
  anyhit_summary.py ncu ncu_K.csv ...     one line per kernel: registers, block, shared bytes,
                                          local load/store sectors, warps active %, active threads
                                          per warp, duration, L1/TEX %
"""
import collections
import csv
import os
import re
import sys


def bench(path):
    runs = collections.OrderedDict()  # (mesh, quality) -> kernel -> [(mrays, hash)]
    tag = None
    for line in open(path):
        if line.startswith("== "):
            mesh, quality, kernel = line.split()[1:4]
            tag = (mesh, quality, kernel)
        m = re.match(r"FOM ([0-9.]+) Mrays/s .* verification ([0-9a-f]+)", line)
        if m and tag:
            runs.setdefault(tag[:2], collections.OrderedDict()).setdefault(tag[2], []).append(
                (float(m.group(1)), m.group(2)))
    for (mesh, quality), kernels in runs.items():
        base = max(r for r, _ in kernels.get("default", [(float("nan"), "")]))
        ref = kernels.get("default", [(0, "")])[0][1]
        print(f"# {mesh} AO {quality}: Grays/s (best of the runs), x default, hash")
        for kernel, rs in kernels.items():
            best = max(r for r, _ in rs)
            worst = min(r for r, _ in rs)
            hashes = {h for _, h in rs}
            same = "same" if hashes == {ref} else "DIFFERS " + ",".join(sorted(hashes))
            print(f"{mesh:16s} {quality:5s} {kernel:20s} {best / 1e3:6.3f} {best / base:6.3f}x "
                  f"{rs[0][1]} {same} ({len(rs)} runs, worst {worst / 1e3:.3f})")
        print()


METRICS = [
    ("launch__registers_per_thread", "regs"),
    ("launch__block_size", "block"),
    ("launch__shared_mem_per_block_dynamic", "shared B"),
    ("l1tex__t_sectors_pipe_lsu_mem_local_op_ld.sum", "local ld"),
    ("l1tex__t_sectors_pipe_lsu_mem_local_op_st.sum", "local st"),
    ("sm__warps_active.avg.pct_of_peak_sustained_active", "warps %"),
    ("smsp__thread_inst_executed_per_inst_executed.ratio", "thr/warp"),
    ("gpu__time_duration.sum", "time"),
    ("l1tex__throughput.avg.pct_of_peak_sustained_active", "L1 %"),
]


def ncu(paths):
    print("kernel               " + " ".join(f"{short:>12s}" for _, short in METRICS))
    for path in paths:
        kernel = os.path.basename(path)[len("ncu_"):-len(".csv")]
        rows = list(csv.reader(line for line in open(path) if line.startswith('"')))
        if not rows:
            print(f"{kernel:20s} (no profile: see {os.path.basename(path)})")
            continue
        header, rows = rows[0], rows[1:]
        values, units = {}, {}
        for r in rows:
            d = dict(zip(header, r))
            values[d["Metric Name"]] = d["Metric Value"]
            units[d["Metric Name"]] = d.get("Metric Unit", "")
        cells = []
        for name, _ in METRICS:
            v = values.get(name, "-")
            if name == "gpu__time_duration.sum" and v != "-":
                v = f"{v} {units[name]}"
            cells.append(f"{v:>12s}")
        print(f"{kernel:20s} " + " ".join(cells))


if __name__ == "__main__":
    if len(sys.argv) < 3 or sys.argv[1] not in ("bench", "ncu"):
        sys.exit(__doc__)
    if sys.argv[1] == "bench":
        bench(sys.argv[2])
    else:
        ncu(sys.argv[2:])
