"""Speed/accuracy sweep of sketchtrace: renders a converged reference, then varies
one knob at a time around a base setting and writes one CSV row per point and
error metric (the sweep format of FORMATS.md, read by the accuracy plot).

  python3 -m rtmini_analysis.sweep --sketchtrace build/miniapps/sketchtrace/sketchtrace \\
      --scene inputs/two_spheres/two_spheres.toml -o sweep.csv [--sketchtrace-double BIN]

Time is the render phase of the run's --summary; memory the run's peak resident
set (os.wait4); errors come from sketchtrace's --reference (RMSE, relative MSE,
PSNR, SSIM against the reference EXR).
"""

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile

from . import cli
from .io import FormatError

# Base point and the values each knob takes (one knob varies at a time).
BASE = {"spp": 4, "shadow-samples": 8, "bounces": 3, "glossy-samples": 1, "bvh": "sah"}
KNOBS = {
    "spp": [1, 2, 4, 8, 16, 32],
    "shadow-samples": [1, 2, 4, 8, 16, 32],
    "bounces": [0, 1, 2, 3, 5, 8],
    "glossy-samples": [1, 2, 4, 8],
    "bvh": ["lbvh", "sah"],
}
# The reference: far beyond every swept value, and another seed, so its samples are
# independent of the swept points' (the same seed would correlate their noise and
# make sample counts that divide 256 look too good).
REFERENCE = {"spp": 256, "shadow-samples": 64, "bounces": 16, "glossy-samples": 16, "bvh": "sah",
             "seed": 987654321}
METRICS = ("rmse", "rel_mse", "ssim_loss")


def flags(settings):
    out = []
    for key, value in settings.items():
        out += [f"--{key}", str(value)]
    return out


def run(binary, scene, size, settings, extra, workdir, tag):
    """One sketchtrace run; returns (summary dict, peak RSS bytes)."""
    summary = os.path.join(workdir, f"{tag}.json")
    cmd = [binary, scene, "--width", str(size[0]), "--height", str(size[1])] + flags(settings)
    cmd += extra + ["--summary", summary]
    with open(os.path.join(workdir, f"{tag}.log"), "w") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise FormatError(f"{scene}: sketchtrace failed ({' '.join(cmd)}); see {log.name}")
    with open(summary, encoding="utf-8") as handle:
        return json.load(handle), usage.ru_maxrss * 1024


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="sweep", description=__doc__.split("\n\n")[0])
    parser.add_argument("--sketchtrace", required=True, help="sketchtrace binary (float build)")
    parser.add_argument("--sketchtrace-double", help="a -DRTMINI_DOUBLE=ON build: adds precision points")
    parser.add_argument("--scene", required=True, help="scene TOML")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    parser.add_argument("--knobs", default=",".join(KNOBS), help="comma list of knobs to vary")
    parser.add_argument("--workdir", help="keep images, logs and summaries here")
    parser.add_argument("-o", "--output", required=True, help="CSV to write")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    knobs = [k for k in args.knobs.split(",") if k]
    unknown = [k for k in knobs if k not in KNOBS]
    if unknown:
        raise FormatError(f"--knobs: unknown {', '.join(unknown)} (known: {', '.join(KNOBS)})")
    workdir = args.workdir or tempfile.mkdtemp(prefix="rtmini_sweep_")
    os.makedirs(workdir, exist_ok=True)
    size = (args.width, args.height)
    scene_name = os.path.splitext(os.path.basename(args.scene))[0]
    reference = os.path.join(workdir, "reference.exr")
    ref_bin = args.sketchtrace_double or args.sketchtrace
    print(f"sweep: reference {REFERENCE} with {ref_bin}", file=sys.stderr)
    run(ref_bin, args.scene, size, REFERENCE, ["-o", reference], workdir, "reference")

    points = [("base", BASE["spp"], "float", BASE)]
    for knob in knobs:
        for value in KNOBS[knob]:
            settings = dict(BASE, **{knob: value})
            if settings != BASE:
                points.append((knob, value, "float", settings))
    if args.sketchtrace_double:
        points.append(("precision", "double", "double", BASE))
    rows = []
    for knob, value, precision, settings in points:
        binary = args.sketchtrace_double if precision == "double" else args.sketchtrace
        tag = f"{knob}_{value}_{precision}"
        summary, rss = run(binary, args.scene, size, settings, ["--reference", reference], workdir, tag)
        errors = summary.get("errors", {})
        values = {"rmse": errors.get("rmse"), "rel_mse": errors.get("rel_mse"),
                  "ssim_loss": None if errors.get("ssim") is None else 1.0 - errors["ssim"]}
        seconds = summary["phases"].get("render", sum(summary["phases"].values()))
        for name in METRICS:
            if values[name] is None:
                raise FormatError(f"{tag}: the summary has no error '{name}'")
            rows.append({"app": "sketchtrace", "scene": scene_name, "knob": knob, "value": value,
                         "precision": precision, "time_s": f"{seconds:.6g}", "memory_bytes": rss,
                         "error_name": name, "error": f"{max(values[name], 0.0):.6g}",
                         "settings": " ".join(flags(settings))})
        print(f"sweep: {tag:28s} {seconds:8.3f} s  rmse {values['rmse']:.5g}", file=sys.stderr)
    tmp = args.output + ".tmp"
    with open(tmp, "w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, args.output)
    print(f"wrote {args.output} ({len(rows)} rows)")
    return 0


if __name__ == "__main__":
    sys.exit(cli.run(main))
