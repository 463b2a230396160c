"""A Markdown and a self-contained HTML report (plots embedded as base64 PNG)
of one run or a sweep of runs, from --timings HDF5 files: per-phase times,
load imbalance (max/mean completion), rays per second, communication share.

  python3 -m rtmini_analysis.timing_report run.h5 [more.h5 ...] -o report
  -> report.md (+ report_files/*.png) and report.html

Definitions: wall = latest phase end (or completion) over ranks; phase time =
max over ranks of end - start; imbalance = max/mean of /ranks/completion_time;
rays/s = sum of /ranks/rays / wall; communication share = sum of
/iterations/allgather_time / (ranks x wall); idle share = sum of
/ranks/idle_time / (ranks x wall).
"""

import argparse
import base64
import html
import os
import sys
import tempfile

import numpy as np

from . import cli, plots
from .io import load_timings
from .rank_completion import completion_stats, strategy_key


def run_metrics(run):
    """The report's numbers for one Timings."""
    completion = run.ranks["completion_time"]
    stats = completion_stats(completion)
    wall = max(float(run.phase_end.max(initial=0.0)), stats["max"])
    rank_seconds = run.nranks * wall
    durations = run.phase_end - run.phase_start
    return {
        "label": run.label,
        "strategy": run.strategy,
        "ranks": run.nranks,
        "threads": int(run.attrs["threads"]),
        "wall_s": wall,
        "imbalance": stats["imbalance"],
        "rays": float(run.ranks["rays"].sum()),
        "rays_per_s": float(run.ranks["rays"].sum()) / wall if wall > 0 else 0.0,
        "comm_share": float(run.iterations["allgather_time"].sum()) / rank_seconds if wall > 0 else 0.0,
        "idle_share": float(run.ranks["idle_time"].sum()) / rank_seconds if wall > 0 else 0.0,
        "bytes_sent": float(run.ranks["bytes_sent"].sum()),
        "phases": [(name, float(durations[:, i].max()), float(durations[:, i].mean()))
                   for i, name in enumerate(run.phase_names)],
        "iterations": int(run.iterations["trace_time"].shape[1]),
    }


def timeline_figure(run):
    """Phases of every rank on one time axis (a Gantt chart)."""
    fig, axes = plots.subplots(1, 1, width=7.0, height=0.35 * run.nranks + 1.6)
    ax = axes[0][0]
    colours = plots.plt.get_cmap("tab10")
    for i, name in enumerate(run.phase_names):
        widths = run.phase_end[:, i] - run.phase_start[:, i]
        ax.barh(np.arange(run.nranks), widths, left=run.phase_start[:, i], height=0.7,
                color=colours(i % 10), label=name)
    ax.set_yticks(np.arange(run.nranks))
    ax.invert_yaxis()
    ax.set_xlabel("seconds since run start")
    ax.set_ylabel("rank")
    ax.set_title(f"{run.label}: phases per rank", fontsize="medium")
    ax.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.0, 0.5))
    fig.tight_layout()
    return fig


def completion_figure(run):
    fig, axes = plots.subplots(1, 2, width=4.2, height=2.8)
    times = run.ranks["completion_time"]
    plots.rank_bars(axes[0][0], times, f"{run.strategy}: by rank")
    plots.rank_bars(axes[0][1], times, f"{run.strategy}: sorted", sort=True, legend=False)
    fig.tight_layout()
    return fig


def sweep_figure(metrics):
    """Wall time and imbalance of every run side by side."""
    fig, axes = plots.subplots(1, 2, width=4.6, height=3.0)
    labels = [f"{m['strategy']}\n{m['ranks']}r" for m in metrics]
    x = np.arange(len(metrics))
    axes[0][0].bar(x, [m["wall_s"] for m in metrics], color="tab:blue")
    axes[0][0].set_ylabel("wall time (s)")
    axes[0][1].bar(x, [m["imbalance"] for m in metrics], color="tab:orange")
    axes[0][1].axhline(1.0, color="k", linestyle="--", linewidth=1)
    axes[0][1].set_ylabel("imbalance (max/mean)")
    for ax in axes[0]:
        ax.set_xticks(x)
        ax.set_xticklabels(labels, fontsize="small")
    fig.suptitle("sweep: wall time and load imbalance")
    fig.tight_layout()
    return fig


def summary_table(metrics):
    header = ("run", "ranks x threads", "wall (s)", "max/mean", "rays/s", "comm share",
              "idle share", "bytes sent")
    rows = [(m["label"], f"{m['ranks']} x {m['threads']}", f"{m['wall_s']:.4g}",
             f"{m['imbalance']:.3f}", f"{m['rays_per_s']:.4g}", f"{100 * m['comm_share']:.1f}%",
             f"{100 * m['idle_share']:.1f}%", f"{m['bytes_sent']:.0f}") for m in metrics]
    return header, rows


def phase_table(m):
    return ("phase", "max over ranks (s)", "mean over ranks (s)"), [
        (name, f"{hi:.4g}", f"{mean:.4g}") for name, hi, mean in m["phases"]]


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def html_table(header, rows):
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>"
                   for row in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def write_atomic(path, text):
    directory = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=directory, suffix=".tmp")
    with os.fdopen(fd, "w", encoding="utf-8") as handle:
        handle.write(text)
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="timing_report", description=__doc__.split("\n\n")[0])
    parser.add_argument("timings", nargs="+", help="--timings HDF5 files (one run, or a sweep)")
    parser.add_argument("-o", "--output", required=True,
                        help="report stem: writes STEM.md, STEM_files/*.png and STEM.html")
    parser.add_argument("--title", default="rtmini timing report")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    runs = [load_timings(path) for path in args.timings]
    runs.sort(key=lambda r: (r.attrs["app"], r.nranks, strategy_key(r.strategy)))
    metrics = [run_metrics(run) for run in runs]
    stem = args.output
    os.makedirs(os.path.dirname(os.path.abspath(stem)), exist_ok=True)
    files_dir = f"{stem}_files"
    os.makedirs(files_dir, exist_ok=True)

    # Each figure goes to a PNG for the Markdown and into the HTML as base64.
    figures = []  # (section index or None, caption, png name, base64)

    def add_figure(fig, section, caption, name):
        path = os.path.join(files_dir, name)
        plots.save_png(fig, path)
        with open(path, "rb") as handle:
            encoded = base64.b64encode(handle.read()).decode("ascii")
        figures.append((section, caption, name, encoded))

    if len(runs) > 1:
        add_figure(sweep_figure(metrics), None, "Wall time and imbalance per run", "sweep.png")
    for i, run in enumerate(runs):
        add_figure(timeline_figure(run), i, "Phases per rank", f"run{i}_timeline.png")
        add_figure(completion_figure(run), i, "Per-rank completion time", f"run{i}_completion.png")

    md = [f"# {args.title}", "", "Generated by `rtmini_analysis.timing_report` from:", ""]
    md += [f"- `{run.path}` ({run.attrs['app']} {run.attrs['version']}, git {run.attrs['git_hash']}, "
           f"{run.attrs['backend']}, scene {run.attrs['scene']}, {run.attrs['created_utc']})" for run in runs]
    header, rows = summary_table(metrics)
    md += ["", "## Summary", "", markdown_table(header, rows), ""]
    body = [f"<h1>{html.escape(args.title)}</h1>", "<ul>"]
    body += [f"<li><code>{html.escape(run.path)}</code> ({html.escape(str(run.attrs['app']))} "
             f"git {html.escape(str(run.attrs['git_hash']))}, {html.escape(str(run.attrs['backend']))}, "
             f"scene {html.escape(str(run.attrs['scene']))})</li>" for run in runs]
    body += ["</ul>", "<h2>Summary</h2>", html_table(header, rows)]
    for section, caption, name, encoded in figures:
        if section is None:
            md += [f"![{caption}]({os.path.basename(files_dir)}/{name})", ""]
            body.append(f'<figure><img alt="{caption}" src="data:image/png;base64,{encoded}">'
                        f"<figcaption>{caption}</figcaption></figure>")
    for i, (run, m) in enumerate(zip(runs, metrics)):
        header, rows = phase_table(m)
        params = ", ".join(f"{k}={v}" for k, v in sorted(run.attrs["parameters"].items()))
        md += [f"## {m['label']}", "", f"Parameters: {params or 'none'}; iterations: {m['iterations']}.",
               "", markdown_table(header, rows), ""]
        body += [f"<h2>{html.escape(m['label'])}</h2>",
                 f"<p>Parameters: {html.escape(params or 'none')}; iterations: {m['iterations']}.</p>",
                 html_table(header, rows)]
        for section, caption, name, encoded in figures:
            if section == i:
                md += [f"![{caption}]({os.path.basename(files_dir)}/{name})", ""]
                body.append(f'<figure><img alt="{caption}" src="data:image/png;base64,{encoded}">'
                            f"<figcaption>{caption}</figcaption></figure>")
    style = ("body{font-family:sans-serif;max-width:60em;margin:auto}table{border-collapse:collapse}"
             "td,th{border:1px solid #999;padding:2px 8px;text-align:right}img{max-width:100%}")
    page = (f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{html.escape(args.title)}"
            f"</title><style>{style}</style></head><body>\n" + "\n".join(body) + "\n</body></html>\n")
    write_atomic(f"{stem}.md", "\n".join(md))
    write_atomic(f"{stem}.html", page)

    print(f"{'run':<40} {'wall_s':>10} {'max/mean':>8} {'rays/s':>12} {'comm':>6} {'idle':>6}")
    for m in metrics:
        print(f"{m['label'].replace(' ', '_'):<40} {m['wall_s']:>10.4f} {m['imbalance']:>8.3f} "
              f"{m['rays_per_s']:>12.4g} {100 * m['comm_share']:>5.1f}% {100 * m['idle_share']:>5.1f}%")
    print(f"wrote {stem}.md {stem}.html")
    return 0


if __name__ == "__main__":
    sys.exit(cli.run(main))
