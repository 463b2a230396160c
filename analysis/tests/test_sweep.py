"""The sweep driver against a stand-in sketchtrace whose error falls with spp."""

import csv
import os
import stat

from conftest import run_tool
from rtmini_analysis.io import load_sweep

# The stand-ins run Debian's /usr/bin/python3 (the suite's Python): a python3 found on PATH may be
# a version manager's shim, 0.5 s a start on the CI machine, and the bake sweep starts 53.
FAKE = """#!/usr/bin/python3
import json, sys
args = sys.argv[1:]
def opt(name, default=None):
    return args[args.index(name) + 1] if name in args else default
if "--width" not in args or "--summary" not in args:
    sys.exit(2)
spp = int(opt("--spp", "1"))
summary = {"phases": {"load": 0.01, "render": 0.001 * spp}}
if "--reference" in args:
    summary["errors"] = {"rmse": 0.1 / spp ** 0.5, "rel_mse": 0.01 / spp, "psnr": 20.0, "ssim": 1 - 0.01 / spp}
if "-o" in args:
    open(opt("-o"), "w").write("image")
json.dump(summary, open(opt("--summary"), "w"))
"""


def fake_binary(tmp_path, body=FAKE):
    path = tmp_path / "sketchtrace"
    path.write_text(body)
    path.chmod(path.stat().st_mode | stat.S_IEXEC)
    return path


def test_sweep_writes_one_row_per_point_and_metric(tmp_path):
    out = tmp_path / "sweep.csv"
    result = run_tool("sweep", "--sketchtrace", fake_binary(tmp_path), "--scene", "two_spheres.toml",
                      "--knobs", "spp,bvh", "--workdir", tmp_path / "w", "-o", out)
    assert result.returncode == 0, result.stderr
    rows = load_sweep(str(out))
    spp_rmse = {r["value"]: r["error"] for r in rows if r["knob"] == "spp" and r["error_name"] == "rmse"}
    # base (spp 4) is its own point; the knob's other values are swept around it
    assert set(spp_rmse) == {"1", "2", "8", "16", "32"}
    assert spp_rmse["1"] > spp_rmse["32"]
    assert {r["error_name"] for r in rows} == {"rmse", "rel_mse", "ssim_loss"}
    assert len(rows) == 3 * (1 + 5 + 1)  # base, 5 spp values, lbvh
    assert os.path.exists(tmp_path / "w" / "reference.exr")


def test_failing_run_is_reported(tmp_path):
    out = tmp_path / "sweep.csv"
    broken = fake_binary(tmp_path, "#!/bin/sh\nexit 3\n")
    result = run_tool("sweep", "--sketchtrace", broken, "--scene", "x.toml", "-o", out)
    assert result.returncode == 2
    assert "sketchtrace failed" in result.stderr
    assert not out.exists()


def test_unknown_knob_is_bad_input(tmp_path):
    result = run_tool("sweep", "--sketchtrace", fake_binary(tmp_path), "--scene", "x.toml",
                      "--knobs", "spp,colour", "-o", tmp_path / "s.csv")
    assert result.returncode == 2
    assert "colour" in result.stderr


# A stand-in bake: its error falls with N and shadow samples; it refuses a reference that is not
# the dense (N = 700) one and records every command line it ran.
FAKE_BAKE = """#!/usr/bin/python3
import json, os, sys
args = sys.argv[1:]
def opt(name, default=None):
    return args[args.index(name) + 1] if name in args else default
if "--summary" not in args or "-o" not in args:
    sys.exit(2)
with open(os.path.join(os.path.dirname(opt("--summary")), "calls.txt"), "a") as log:
    log.write(" ".join(args) + "\\n")
n, s = int(opt("--viewpoints", "100")), int(opt("--shadow-samples", "16"))
summary = {"phases": {"read": 0.5, "base": 0.001 * s, "iterate": 0.0001 * n, "total": 1.0}}
if "--reference" in args:
    ref = json.load(open(opt("--reference")))
    if ref["n"] != 700:
        sys.exit(2)
    e = 1.0 / n ** 0.5 + 0.1 / s + (0.5 if ref["gather"] else 0.0) / (1 + int(opt("--gather-rays", "0")))
    summary["errors"] = {"rmse": e, "rel_mse": e * e, "mean_abs": e / 2, "max_abs": 3 * e,
                         "view_dependent_rmse": 2 * e, "view_independent_rmse": e / 3}
    if n == 700:
        summary["errors"]["stored"] = {"rmse": 1e-7, "rel_mse": 1e-14, "mean_abs": 1e-8,
                                       "view_dependent_rmse": 0, "view_independent_rmse": 0}
json.dump({"n": n, "gather": int(opt("--gather-rays", "0")) > 0}, open(opt("-o"), "w"))
json.dump(summary, open(opt("--summary"), "w"))
"""


def test_bake_sweep_compares_every_point_with_the_dense_reference(tmp_path):
    out = tmp_path / "bake.csv"
    fake = tmp_path / "bake"
    fake.write_text(FAKE_BAKE)
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    work = tmp_path / "w"
    result = run_tool("sweep", "--bake", fake, "--bake-double", fake, "--scene", "cornell.bs", "--repeat", 2,
                      "--knobs", "viewpoints,shadow-samples,gather-rays", "--workdir", work, "-o", out)
    assert result.returncode == 0, result.stderr
    rows = load_sweep(str(out))
    assert {r["app"] for r in rows} == {"bake"}
    rmse = {(r["knob"], r["value"]): r["error"] for r in rows if r["error_name"] == "rmse"}
    n_values = ["20", "50", "100", "500", "1000", "2000"]  # 200 is the base point
    assert [rmse[("viewpoints", n)] for n in n_values] == sorted(
        [rmse[("viewpoints", n)] for n in n_values], reverse=True)
    assert rmse[("shadow-samples", "1")] > rmse[("shadow-samples", "256")]
    # gather points (0 included) are compared with the gather reference, under their own names
    gather = {r["value"]: r["error"] for r in rows if r["error_name"] == "rmse_vs_gather256"}
    assert set(gather) == {"0", "4", "16", "64"}
    assert gather["0"] > gather["64"]
    assert ("precision", "double") in rmse
    assert rmse[("traced-reference", "float")] == 1e-7  # colour by colour, not through the lookup
    # time is the base + iterate phases, not the whole run
    base = next(r for r in rows if r["knob"] == "base" and r["error_name"] == "rmse")
    assert abs(base["time_s"] - (0.016 + 0.02)) < 1e-9
    calls = (work / "calls.txt").read_text().splitlines()
    traced = [c for c in calls if "--trace-reference" in c and "--reference" not in c.split()
              and "/reference.bs" in c]
    assert len(traced) == 1  # one traced reference for every point
    assert all("--viewpoints 700" in c and "--shadow-samples 1024" in c and
               "--seed 987654321" in c for c in traced)
    # every point runs twice alone (timed, --repeat 2) and once against the reference
    assert 2 * sum("--reference" in c for c in calls) == sum("--reference" not in c for c in calls) - 2
    assert not list(work.glob("base_*.bs"))  # point maps are removed after the error run


def test_bake_knob_of_sketchtrace_is_bad_input(tmp_path):
    result = run_tool("sweep", "--bake", "bake", "--scene", "x.bs", "--knobs", "spp",
                      "-o", tmp_path / "s.csv")
    assert result.returncode == 2
    assert "spp" in result.stderr
