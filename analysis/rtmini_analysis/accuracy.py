"""Error versus time from sweep CSVs, one panel per (app, scene, error metric),
one series per (knob, precision), with the Pareto frontier drawn and printed.

  python3 -m rtmini_analysis.accuracy sweep-spp.csv sweep-float.csv -o accuracy.png

A point is on the frontier when no other point is at least as fast and at least
as accurate while strictly better in one of the two.
"""

import argparse
import sys

from . import cli, plots
from .io import load_sweep


def pareto_front(rows):
    """The non-dominated rows (minimise time_s and error), ordered by time."""
    ordered = sorted(rows, key=lambda r: (r["time_s"], r["error"]))
    front, best_error = [], float("inf")
    for row in ordered:
        if row["error"] < best_error:
            front.append(row)
            best_error = row["error"]
    return front


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="accuracy", description=__doc__.split("\n\n")[0])
    parser.add_argument("sweeps", nargs="+", help="sweep CSV files")
    parser.add_argument("-o", "--output", required=True, help="PNG to write")
    parser.add_argument("--error-name", help="only this error metric (e.g. rmse)")
    parser.add_argument("--linear", action="store_true", help="linear instead of log axes")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    rows = [row for path in args.sweeps for row in load_sweep(path)]
    if args.error_name:
        rows = [r for r in rows if r["error_name"] == args.error_name]
        if not rows:
            print(f"accuracy: no rows with error_name '{args.error_name}'", file=sys.stderr)
            return 2
    panels = {}
    for row in rows:
        panels.setdefault((row["app"], row["scene"], row["error_name"]), []).append(row)

    fig, axes = plots.subplots(1, len(panels), width=5.0, height=3.8)
    print(f"{'app':<12} {'scene':<16} {'error_name':<10} {'knob':<14} {'value':>8} "
          f"{'precision':<9} {'time_s':>10} {'error':>12}")
    for ax, ((app, scene, error_name), points) in zip(axes[0], sorted(panels.items())):
        series = {}
        for row in points:
            series.setdefault((row["knob"], row["precision"]), []).append(row)
        for (knob, precision), members in sorted(series.items()):
            members.sort(key=lambda r: r["time_s"])
            ax.plot([r["time_s"] for r in members], [r["error"] for r in members], "o",
                    alpha=0.75, label=f"{knob} ({precision})")
            for r in members:
                ax.annotate(r["value"], (r["time_s"], r["error"]), fontsize="x-small",
                            textcoords="offset points", xytext=(3, 3))
        front = pareto_front(points)
        ax.step([r["time_s"] for r in front], [r["error"] for r in front], "k-", where="post",
                linewidth=1.2, label="Pareto frontier")
        for r in front:
            print(f"{app:<12} {scene:<16} {error_name:<10} {r['knob']:<14} {r['value']:>8} "
                  f"{r['precision']:<9} {r['time_s']:>10.4g} {r['error']:>12.4g}")
        positive = all(r["time_s"] > 0 and r["error"] > 0 for r in points)
        if positive and not args.linear:
            ax.set_xscale("log")
            ax.set_yscale("log")
            plots.plain_ticks(ax, "x")
            plots.plain_ticks(ax, "y")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(error_name)
        ax.set_title(f"{app}, {scene}: {error_name} vs time", fontsize="medium")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize="small")
    fig.tight_layout()
    plots.save_png(fig, args.output)
    print(f"wrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(cli.run(main))
