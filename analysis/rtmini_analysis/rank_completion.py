"""Per-rank completion times, unsorted and sorted, one row of panels per
load-balancing strategy (the hand-drawn ray-tracing paper's figures), with
max, mean and imbalance (max/mean) printed per strategy.

  python3 -m rtmini_analysis.rank_completion run-static.h5 run-bargain.h5 -o ranks.png
"""

import argparse
import sys

import numpy as np

from . import cli, plots
from .io import FormatError, load_timings

# The ladder of the seed paper first (naive -> metric -> chunks -> bargaining),
# then the other strategies the apps offer.
STRATEGY_ORDER = ("static", "metric", "cost", "chunks", "bargain", "queue", "steal")


def strategy_key(name):
    return (STRATEGY_ORDER.index(name), name) if name in STRATEGY_ORDER else (len(STRATEGY_ORDER), name)


def completion_stats(times):
    """max, mean, min and imbalance (max/mean; 1 is perfect balance) of per-rank times."""
    times = np.asarray(times, dtype=float)
    mean = float(times.mean())
    return {"max": float(times.max()), "mean": mean, "min": float(times.min()),
            "imbalance": float(times.max() / mean) if mean > 0 else float("nan")}


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="rank_completion", description=__doc__.split("\n\n")[0])
    parser.add_argument("timings", nargs="+", help="--timings HDF5 files, one per strategy")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    parser.add_argument("--title", help="figure title (default: app, scene and rank count)")
    parser.add_argument("--labels", help="comma list of row labels, one per file in the given order "
                        "(default: each file's strategy, which must then differ)")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    runs = [load_timings(path) for path in args.timings]
    if args.labels:
        labels = args.labels.split(",")
        if len(labels) != len(runs):
            raise FormatError(f"--labels: {len(labels)} labels for {len(runs)} files")
    else:
        seen = {}
        for run in runs:
            if run.strategy in seen:
                raise FormatError(f"{run.path}: strategy '{run.strategy}' already given by {seen[run.strategy]}"
                                  " (use --labels)")
            seen[run.strategy] = run.path
        runs.sort(key=lambda r: strategy_key(r.strategy))
        labels = [run.strategy for run in runs]

    fig, axes = plots.subplots(len(runs), 2, width=4.6, height=2.6)
    print(f"{'strategy':<10} {'ranks':>5} {'max_s':>10} {'mean_s':>10} {'min_s':>10} {'max/mean':>8}")
    # One y scale for every panel, so strategies compare at a glance.
    ymax = 1.08 * max(float(run.ranks["completion_time"].max()) for run in runs) or None
    for row, (run, name) in enumerate(zip(runs, labels)):
        times = run.ranks["completion_time"]
        stats = completion_stats(times)
        print(f"{name:<10} {run.nranks:>5} {stats['max']:>10.4f} {stats['mean']:>10.4f} "
              f"{stats['min']:>10.4f} {stats['imbalance']:>8.3f}")
        label = f"{name}: max/mean {stats['imbalance']:.2f}"
        plots.rank_bars(axes[row][0], times, f"{label} (by rank)", ymax=ymax, legend=row == 0)
        plots.rank_bars(axes[row][1], times, f"{label} (sorted)", sort=True, ymax=ymax, legend=False)
    first = runs[0].attrs
    fig.suptitle(args.title or f"{first['app']}: per-rank completion, {first['scene']}, "
                 f"{first['ranks']} ranks x {first['threads']} threads")
    fig.tight_layout()
    plots.save_png(fig, args.output)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(cli.run(main))
