"""The sweep driver against a stand-in sketchtrace whose error falls with spp."""

import csv
import os
import stat

from conftest import run_tool
from rtmini_analysis.io import load_sweep

FAKE = """#!/usr/bin/env python3
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
