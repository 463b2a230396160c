"""Loading and validating the files the apps write (see analysis/FORMATS.md).

Every loader raises FormatError("file: reason") or ("file:line: reason") on bad
input; the command-line tools print it and exit 2, like the apps.
"""

import csv
import json
import math
from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np

TIMINGS_ROOT_ATTRS = ("app", "version", "git_hash", "backend", "ranks", "threads",
                      "strategy", "scene", "parameters", "created_utc")
CHUNK_FIELDS = ("rank", "iteration", "start", "end", "work_units", "rays")
RANK_FIELDS = ("completion_time", "idle_time", "messages_sent", "bytes_sent", "rays",
               "work_units")
ITERATION_FIELDS = ("trace_time", "allgather_time", "allgather_bytes", "write_time")
SUMMARY_KEYS = ("app", "version", "git_hash", "backend", "ranks", "threads", "scene",
                "parameters", "phases", "figure_of_merit", "verification_hash",
                "peak_memory_bytes")
SWEEP_COLUMNS = ("app", "scene", "knob", "value", "precision", "time_s", "memory_bytes",
                 "error_name", "error")
SWEEP_NUMERIC = ("time_s", "memory_bytes", "error")


class FormatError(Exception):
    """A file that does not follow FORMATS.md; the message starts with the file name."""


@dataclass
class Timings:
    """One run's --timings file, as numpy arrays (seconds since run start)."""

    path: str
    attrs: Dict[str, object]
    phase_names: List[str]
    phase_start: np.ndarray  # [ranks, phases]
    phase_end: np.ndarray  # [ranks, phases]
    chunks: Dict[str, np.ndarray] = field(default_factory=dict)  # 1D each
    ranks: Dict[str, np.ndarray] = field(default_factory=dict)  # [ranks] each
    iterations: Dict[str, np.ndarray] = field(default_factory=dict)  # [ranks, iterations]

    @property
    def nranks(self) -> int:
        return int(self.attrs["ranks"])

    @property
    def strategy(self) -> str:
        return str(self.attrs["strategy"])

    @property
    def label(self) -> str:
        return f"{self.attrs['app']} {self.strategy} ({self.nranks} ranks)"


def _text(value) -> str:
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray) and value.shape == ():
        return _text(value[()])
    return str(value)


def _attr(path, attrs, name):
    if name not in attrs:
        raise FormatError(f"{path}: missing root attribute '{name}'")
    value = attrs[name]
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.reshape(()).item()
    if name in ("ranks", "threads"):
        try:
            number = int(value)
        except (TypeError, ValueError):
            raise FormatError(f"{path}: attribute '{name}' is not an integer: {value!r}")
        if number < 1:
            raise FormatError(f"{path}: attribute '{name}' must be >= 1, got {number}")
        return number
    return _text(value)


def _dataset(path, handle, name, shape=None):
    if name not in handle:
        raise FormatError(f"{path}: missing dataset '/{name}'")
    data = np.asarray(handle[name][()], dtype=np.float64)
    if shape is not None and data.shape != shape:
        raise FormatError(f"{path}: dataset '/{name}' has shape {data.shape}, expected {shape}")
    if not np.all(np.isfinite(data)):
        raise FormatError(f"{path}: dataset '/{name}' holds NaN or infinity")
    return data


def load_timings(path: str) -> Timings:
    """Read and check one --timings HDF5 file."""
    import h5py  # only the HDF5 tools need it

    try:
        handle = h5py.File(path, "r")
    except OSError as err:
        raise FormatError(f"{path}: not a readable HDF5 file ({err})")
    with handle:
        attrs = {name: _attr(path, handle.attrs, name) for name in TIMINGS_ROOT_ATTRS}
        try:
            attrs["parameters"] = json.loads(attrs["parameters"])
        except json.JSONDecodeError as err:
            raise FormatError(f"{path}: attribute 'parameters' is not JSON ({err})")
        nranks = attrs["ranks"]
        if "phases/names" not in handle:
            raise FormatError(f"{path}: missing dataset '/phases/names'")
        names = [_text(n) for n in handle["phases/names"][()]]
        shape = (nranks, len(names))
        start = _dataset(path, handle, "phases/start", shape)
        end = _dataset(path, handle, "phases/end", shape)
        if np.any(end < start):
            raise FormatError(f"{path}: a phase ends before it starts")
        chunks = {f: _dataset(path, handle, f"chunks/{f}") for f in CHUNK_FIELDS}
        lengths = {a.shape for a in chunks.values()}
        if len(lengths) != 1 or len(next(iter(lengths))) != 1:
            raise FormatError(f"{path}: /chunks datasets must be 1D and of equal length")
        if chunks["rank"].size and (chunks["rank"].min() < 0 or chunks["rank"].max() >= nranks):
            raise FormatError(f"{path}: /chunks/rank holds a rank outside 0..{nranks - 1}")
        ranks = {f: _dataset(path, handle, f"ranks/{f}", (nranks,)) for f in RANK_FIELDS}
        iterations = {f: _dataset(path, handle, f"iterations/{f}") for f in ITERATION_FIELDS}
        for f, data in iterations.items():
            if data.size == 0:  # zero iterations: h5py may give shape (0,) or (ranks, 0)
                iterations[f] = data.reshape(nranks, 0)
            elif data.ndim != 2 or data.shape[0] != nranks:
                raise FormatError(f"{path}: dataset '/iterations/{f}' has shape {data.shape}, "
                                  f"expected ({nranks}, iterations)")
        if len({a.shape for a in iterations.values()}) != 1:
            raise FormatError(f"{path}: /iterations datasets differ in shape")
    return Timings(path, attrs, names, start, end, chunks, ranks, iterations)


def load_summary(path: str) -> dict:
    """Read and check one --summary JSON file."""
    try:
        with open(path, encoding="utf-8") as handle:
            summary = json.load(handle)
    except OSError as err:
        raise FormatError(f"{path}: cannot read ({err.strerror})")
    except json.JSONDecodeError as err:
        raise FormatError(f"{path}:{err.lineno}: not JSON ({err.msg})")
    if not isinstance(summary, dict):
        raise FormatError(f"{path}:1: top level must be an object")
    for key in SUMMARY_KEYS:
        if key not in summary:
            raise FormatError(f"{path}: missing key '{key}'")
    for key in ("ranks", "threads"):
        if not isinstance(summary[key], int) or summary[key] < 1:
            raise FormatError(f"{path}: '{key}' must be a positive integer")
    phases = summary["phases"]
    if not isinstance(phases, dict) or not phases:
        raise FormatError(f"{path}: 'phases' must be a non-empty object")
    for name, seconds in phases.items():
        if not isinstance(seconds, (int, float)) or not math.isfinite(seconds) or seconds < 0:
            raise FormatError(f"{path}: phase '{name}' is not a non-negative number")
    fom = summary["figure_of_merit"]
    if not isinstance(fom, dict) or not {"name", "value", "unit"} <= fom.keys():
        raise FormatError(f"{path}: 'figure_of_merit' needs name, value and unit")
    summary["_path"] = path
    return summary


def run_time(summary: dict) -> float:
    """Wall time of a run: the 'total' phase, else the sum of all phases."""
    phases = summary["phases"]
    return float(phases["total"]) if "total" in phases else float(sum(phases.values()))


def load_sweep(path: str) -> List[dict]:
    """Read one sweep CSV: a list of rows, numeric columns as float."""
    try:
        handle = open(path, newline="", encoding="utf-8")
    except OSError as err:
        raise FormatError(f"{path}: cannot read ({err.strerror})")
    with handle:
        reader = csv.DictReader(handle)
        missing = [c for c in SWEEP_COLUMNS if c not in (reader.fieldnames or [])]
        if missing:
            raise FormatError(f"{path}:1: missing column(s) {', '.join(missing)}")
        rows = []
        for row in reader:
            line = reader.line_num
            for column in SWEEP_NUMERIC:
                try:
                    row[column] = float(row[column])
                except (TypeError, ValueError):
                    raise FormatError(f"{path}:{line}: '{column}' is not a number: "
                                      f"{row[column]!r}")
                if not math.isfinite(row[column]) or row[column] < 0:
                    raise FormatError(f"{path}:{line}: '{column}' must be finite and >= 0")
            row["_where"] = f"{path}:{line}"
            rows.append(row)
    if not rows:
        raise FormatError(f"{path}:2: no data rows")
    return rows
