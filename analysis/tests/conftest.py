"""Synthetic inputs in FORMATS.md layout, and a runner for the tools' CLIs."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

ANALYSIS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ANALYSIS_DIR)


def write_timings(path, completion, strategy="static", app="sketchtrace", iterations=0,
                  rays=None, allgather=None, phases=("setup", "trace", "write")):
    """A --timings file whose ranks finish at the given times; phases split each
    rank's time evenly, one chunk per rank, `iterations` equal bake iterations."""
    import h5py

    completion = np.asarray(completion, dtype=float)
    nranks = completion.size
    rays = np.full(nranks, 1000.0) if rays is None else np.asarray(rays, dtype=float)
    bounds = completion[:, None] * np.linspace(0.0, 1.0, len(phases) + 1)[None, :]
    with h5py.File(path, "w") as f:
        for key, value in {"app": app, "version": "0.1.0", "git_hash": "abc123", "backend": "Serial",
                           "strategy": strategy, "scene": "two_spheres",
                           "parameters": json.dumps({"spp": 4}),
                           "created_utc": "2024-01-01T00:00:00Z"}.items():
            f.attrs[key] = value
        f.attrs["ranks"] = np.int32(nranks)
        f.attrs["threads"] = np.int32(2)
        f.create_dataset("phases/names", data=list(phases), dtype=h5py.string_dtype())
        f["phases/start"] = bounds[:, :-1]
        f["phases/end"] = bounds[:, 1:]
        f["chunks/rank"] = np.arange(nranks, dtype=np.int32)
        f["chunks/iteration"] = np.zeros(nranks, dtype=np.int32)
        f["chunks/start"] = np.zeros(nranks)
        f["chunks/end"] = completion
        f["chunks/work_units"] = np.full(nranks, 10, dtype=np.int64)
        f["chunks/rays"] = rays.astype(np.int64)
        f["ranks/completion_time"] = completion
        f["ranks/idle_time"] = completion.max() - completion
        f["ranks/messages_sent"] = np.full(nranks, 3, dtype=np.int64)
        f["ranks/bytes_sent"] = np.full(nranks, 4096, dtype=np.int64)
        f["ranks/rays"] = rays.astype(np.int64)
        f["ranks/work_units"] = np.full(nranks, 10, dtype=np.int64)
        trace = np.tile(completion[:, None] / max(iterations, 1), (1, iterations))
        gather = np.zeros_like(trace) if allgather is None else np.full_like(trace, allgather)
        f["iterations/trace_time"] = trace
        f["iterations/allgather_time"] = gather
        f["iterations/allgather_bytes"] = np.full_like(trace, 1024)
        f["iterations/write_time"] = np.zeros_like(trace)


def write_summary(path, ranks, total, app="bake", threads=1, phases=None, fom=1.0):
    summary = {"app": app, "version": "0.1.0", "git_hash": "abc123", "backend": "OpenMP",
               "ranks": ranks, "threads": threads, "scene": {"name": "cornell", "triangles": 36},
               "parameters": {"viewpoints": 100}, "phases": phases or {"total": total},
               "figure_of_merit": {"name": "rays_per_second", "value": fom, "unit": "rays/s"},
               "verification_hash": "deadbeef", "peak_memory_bytes": 1 << 20}
    with open(path, "w", encoding="utf-8") as handle:
        json.dump(summary, handle)


def run_tool(tool, *args):
    """Run `python3 -m rtmini_analysis.<tool> args` as a user would; returns CompletedProcess."""
    env = dict(os.environ, PYTHONPATH=ANALYSIS_DIR, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, "-m", f"rtmini_analysis.{tool}", *map(str, args)],
                          capture_output=True, text=True, env=env, cwd=ANALYSIS_DIR, timeout=120)


def parse_table(stdout, key_column=0):
    """Rows of a printed whitespace table as {first cell: [cells]} (header line skipped)."""
    lines = [line.split() for line in stdout.splitlines() if line.strip()]
    return {cells[key_column]: cells for cells in lines[1:] if not cells[0].startswith("wrote")}


def assert_png(path, min_width=200, min_height=150):
    """The PNG exists, is at least the given size and is not one flat colour."""
    import matplotlib.image

    assert os.path.getsize(path) > 2000, f"{path} is suspiciously small"
    image = matplotlib.image.imread(path)
    height, width = image.shape[:2]
    assert width >= min_width and height >= min_height, (width, height)
    assert float(image[..., :3].std()) > 0.01, f"{path} is blank"
    return width, height


@pytest.fixture
def tools():
    return run_tool
