"""Plotting helpers shared by the tools: Agg backend, atomic PNG writes,
per-rank bar charts."""

import os
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend must be chosen first)
import numpy as np  # noqa: E402
from matplotlib.ticker import FormatStrFormatter, MaxNLocator  # noqa: E402

DPI = 120


def subplots(nrows=1, ncols=1, width=5.0, height=3.2, **kwargs):
    """A figure of nrows x ncols panels, each about width x height inches; axes always 2D."""
    fig, axes = plt.subplots(nrows, ncols, figsize=(width * ncols, height * nrows),
                             squeeze=False, **kwargs)
    return fig, axes


def save_png(fig, path):
    """Write fig as PNG via a temp file and rename, so no half-written plot is left."""
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".png", dir=directory)
    try:
        with os.fdopen(fd, "wb") as handle:
            fig.savefig(handle, format="png", dpi=DPI, bbox_inches="tight")
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
    finally:
        plt.close(fig)


def rank_bars(ax, values, title, sort=False, ylabel="completion time (s)", ymax=None, legend=True):
    """Per-rank bars with lines at the maximum and mean, unsorted or sorted ascending
    (the two views of the hand-drawn paper's load-balance figures); ymax shares a scale."""
    values = np.asarray(values, dtype=float)
    shown = np.sort(values) if sort else values
    ax.bar(np.arange(shown.size), shown, width=0.8, color="tab:blue")
    if shown.size:
        ax.axhline(shown.max(), color="tab:red", linestyle="--", linewidth=1, label="max")
        ax.axhline(shown.mean(), color="tab:gray", linestyle=":", linewidth=1, label="mean")
        if legend:
            ax.legend(loc="lower right", fontsize="small", framealpha=0.9)
    ax.set_title(title, fontsize="medium")
    ax.set_xlabel("rank (sorted by completion)" if sort else "rank")
    ax.set_ylabel(ylabel)
    ax.set_xlim(-0.6, max(shown.size, 1) - 0.4)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_ylim(0, ymax if ymax else None)


def plain_ticks(ax, axis="y"):
    """Label a log axis as plain numbers (0.5, 2, 16) instead of powers."""
    target = ax.yaxis if axis == "y" else ax.xaxis
    target.set_major_formatter(FormatStrFormatter("%g"))
    target.set_minor_formatter(FormatStrFormatter(""))
