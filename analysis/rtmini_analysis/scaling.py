"""Strong or weak scaling from --summary JSON files: time, speedup and parallel
efficiency against rank count, with the ideal lines; prints the table.

  python3 -m rtmini_analysis.scaling --mode strong runs/strong-*.json -o strong.png

Speedup and efficiency are relative to the smallest rank count p0 measured:
strong S(p) = p0 T(p0) / T(p), E = S/p; weak E = T(p0) / T(p), S = p E (scaled).
Repeated runs at one rank count are reduced to their median time.
"""

import argparse
import sys

import numpy as np

from . import cli, plots
from .io import FormatError, load_summary, run_time


def scaling_table(points, mode):
    """points: {ranks: [times]} -> rows of (ranks, time, speedup, efficiency)."""
    ranks = sorted(points)
    times = [float(np.median(points[p])) for p in ranks]
    p0, t0 = ranks[0], times[0]
    rows = []
    for p, t in zip(ranks, times):
        if t <= 0:
            raise FormatError(f"run time at {p} ranks is {t}; cannot compute speedup")
        if mode == "strong":
            speedup = p0 * t0 / t
            efficiency = speedup / p
        else:
            efficiency = t0 / t
            speedup = p * efficiency
        rows.append((p, t, speedup, efficiency))
    return rows


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="scaling", description=__doc__.split("\n\n")[0])
    parser.add_argument("summaries", nargs="+", help="--summary JSON files, one per run")
    parser.add_argument("--mode", choices=("strong", "weak"), default="strong")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    parser.add_argument("--title", help="figure title")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    summaries = [load_summary(path) for path in args.summaries]
    apps = {s["app"] for s in summaries}
    if len(apps) != 1:
        raise FormatError(f"{summaries[0]['_path']}: runs of different apps mixed: {sorted(apps)}")
    points = {}
    for s in summaries:
        if run_time(s) <= 0:
            raise FormatError(f"{s['_path']}: run time is {run_time(s)} s; cannot compute speedup")
        points.setdefault(s["ranks"], []).append(run_time(s))
    rows = scaling_table(points, args.mode)
    threads = sorted({s["threads"] for s in summaries})

    print(f"{'ranks':>5} {'time_s':>10} {'speedup':>8} {'efficiency':>10}")
    for p, t, speedup, efficiency in rows:
        print(f"{p:>5} {t:>10.4f} {speedup:>8.3f} {efficiency:>10.3f}")

    ranks = np.array([r[0] for r in rows], dtype=float)
    times = np.array([r[1] for r in rows])
    fig, axes = plots.subplots(1, 3, width=4.0, height=3.2)
    ax_time, ax_speed, ax_eff = axes[0]
    ideal_time = times[0] * ranks[0] / ranks if args.mode == "strong" else np.full_like(ranks, times[0])
    ax_time.plot(ranks, times, "o-", label="measured")
    ax_time.plot(ranks, ideal_time, "k--", linewidth=1, label="ideal")
    ax_time.set_xscale("log", base=2)
    ax_time.set_yscale("log")
    ax_time.set_ylabel("time (s)")
    ax_speed.plot(ranks, [r[2] for r in rows], "o-", label="measured")
    ax_speed.plot(ranks, ranks, "k--", linewidth=1, label="ideal")
    ax_speed.set_xscale("log", base=2)
    ax_speed.set_yscale("log", base=2)
    ax_speed.set_ylabel("scaled speedup" if args.mode == "weak" else "speedup")
    ax_eff.plot(ranks, [r[3] for r in rows], "o-", label="measured")
    ax_eff.axhline(1.0, color="k", linestyle="--", linewidth=1, label="ideal")
    ax_eff.set_xscale("log", base=2)
    ax_eff.set_ylim(0, max(1.1, max(r[3] for r in rows) * 1.05))
    ax_eff.set_ylabel("parallel efficiency")
    for ax in (ax_time, ax_speed, ax_eff):
        ax.set_xlabel("MPI ranks")
        ax.set_xticks(ranks)
        ax.set_xticklabels([str(int(p)) for p in ranks])
        ax.grid(True, which="major", alpha=0.3)
    for ax in (ax_time, ax_speed):
        plots.plain_ticks(ax)
        ax.legend(fontsize="small")
    scene = summaries[0]["scene"].get("name", "") if isinstance(summaries[0]["scene"], dict) else ""
    fig.suptitle(args.title or f"{summaries[0]['app']} {args.mode} scaling {scene} "
                 f"({'/'.join(map(str, threads))} thread(s) per rank)")
    fig.tight_layout()
    plots.save_png(fig, args.output)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(cli.run(main))
