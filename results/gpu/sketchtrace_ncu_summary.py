#!/usr/bin/env python3
"""Summarise ncu's CSV (--csv --print-units base) of sketchtrace's render launches.

Usage: sketchtrace_ncu_summary.py NCU_CSV
Prints one line per PixelKernel launch (grid, time, registers, local load/store sectors, warps
active, threads per instruction) and a line over all launches: total time and sectors, and
warps active and threads per instruction weighted by each launch's time. Lines of the file that
are not ncu's CSV (the program's own output) are skipped.
"""
import csv
import sys

TIME = "gpu__time_duration.sum"
REGS = "launch__registers_per_thread"
LD = "l1tex__t_sectors_pipe_lsu_mem_local_op_ld.sum"
ST = "l1tex__t_sectors_pipe_lsu_mem_local_op_st.sum"
WARPS = "sm__warps_active.avg.pct_of_peak_sustained_active"
THREADS = "smsp__thread_inst_executed_per_inst_executed.ratio"


def number(text):
    try:
        return float(text.replace(",", ""))
    except ValueError:
        return float("nan")


def main(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        rows = [line for line in f if line.startswith('"')]
    launches = {}
    order = []
    for row in csv.DictReader(rows):
        if "PixelKernel" not in row.get("Kernel Name", ""):
            continue
        key = row["ID"]
        if key not in launches:
            launches[key] = {"grid": row.get("Grid Size", "?")}
            order.append(key)
        launches[key][row["Metric Name"]] = number(row["Metric Value"])
    if not order:
        print("  no PixelKernel launch in", path)
        return 1
    total = {"time": 0.0, LD: 0.0, ST: 0.0, WARPS: 0.0, THREADS: 0.0}
    for key in order:
        m = launches[key]
        t = m.get(TIME, 0.0)
        print(f"  launch {key:>3} grid {m['grid']:>12}: {t / 1e6:9.3f} ms, "
              f"{m.get(REGS, float('nan')):.0f} registers, local ld/st "
              f"{m.get(LD, 0) / 1e6:.2f}M / {m.get(ST, 0) / 1e6:.2f}M sectors, "
              f"warps active {m.get(WARPS, float('nan')):.2f} %, "
              f"threads/inst {m.get(THREADS, float('nan')):.2f}")
        total["time"] += t
        total[LD] += m.get(LD, 0)
        total[ST] += m.get(ST, 0)
        total[WARPS] += t * m.get(WARPS, 0)
        total[THREADS] += t * m.get(THREADS, 0)
    t = total["time"]
    print(f"  all {len(order)} launches: {t / 1e6:.3f} ms, local ld/st "
          f"{total[LD] / 1e6:.2f}M / {total[ST] / 1e6:.2f}M sectors, warps active "
          f"{total[WARPS] / t if t else float('nan'):.2f} % and threads/inst "
          f"{total[THREADS] / t if t else float('nan'):.2f} (time-weighted)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
