"""Speed/accuracy sweep of sketchtrace or bake: makes a converged reference, then
varies one knob at a time around a base setting and writes one CSV row per point
and error metric (the sweep format of FORMATS.md, read by the accuracy plot).

  python3 -m rtmini_analysis.sweep --sketchtrace build/miniapps/sketchtrace/sketchtrace \\
      --scene inputs/two_spheres/two_spheres.toml -o sweep.csv [--sketchtrace-double BIN]
  python3 -m rtmini_analysis.sweep --bake build/miniapps/bake/bake \\
      --scene inputs/cornell_big/cornell_big_raw.bs -o sweep.csv [--bake-double BIN]

sketchtrace: time is the render phase of the run's --summary; memory the run's
peak resident set (os.wait4); errors come from sketchtrace's --reference (RMSE,
relative MSE, SSIM against the reference EXR).

bake: the reference is `bake --trace-reference` with 700 viewpoints (every colour
traced directly along its direction, many shadow samples, more mirror bounces than
any point, another seed; the double build when given). bake --reference reads each
point's map along the reference's 700 directions per vertex with the bake's lookup,
so every N is measured on the same directions, between its own viewpoints too.
Each point runs alone (--repeat times; time = the fastest base + iterate phases,
memory = peak RSS) and once with --reference (RMSE, relative MSE, mean |error| over
every vertex and reference direction, RMSE of the view-dependent and of the other
vertices), so holding the reference does not count as the bake's memory. Gather rays add light the traced reference does not model: those points
are compared with a bake of 256 gather rays instead (error names `*_vs_gather256`).
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


def run_command(app, cmd, scene, workdir, tag):
    """Runs cmd (which writes --summary WORKDIR/TAG.json); returns (summary, peak RSS bytes)."""
    summary = os.path.join(workdir, f"{tag}.json")
    cmd = [str(c) for c in cmd] + ["--summary", summary]
    with open(os.path.join(workdir, f"{tag}.log"), "w") as log:
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(proc.pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        raise FormatError(f"{scene}: {app} failed ({' '.join(cmd)}); see {log.name}")
    with open(summary, encoding="utf-8") as handle:
        return json.load(handle), usage.ru_maxrss * 1024


def run(binary, scene, size, settings, extra, workdir, tag):
    """One sketchtrace run; returns (summary dict, peak RSS bytes)."""
    cmd = [binary, scene, "--width", str(size[0]), "--height", str(size[1])] + flags(settings)
    return run_command("sketchtrace", cmd + extra, scene, workdir, tag)


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="sweep", description=__doc__.split("\n\n")[0])
    app = parser.add_mutually_exclusive_group(required=True)
    app.add_argument("--sketchtrace", help="sketchtrace binary (float build)")
    app.add_argument("--bake", help="bake binary (float build): sweeps the bake knobs")
    parser.add_argument("--sketchtrace-double", help="a -DRTMINI_DOUBLE=ON build: adds precision points")
    parser.add_argument("--bake-double", help="a -DRTMINI_DOUBLE=ON bake: precision points, reference")
    parser.add_argument("--scene", required=True, help="scene TOML (sketchtrace) or .bs (bake)")
    parser.add_argument("--width", type=int, default=160)
    parser.add_argument("--height", type=int, default=120)
    parser.add_argument("--repeat", type=int, default=1,
                        help="bake: timed runs per point, the fastest counts (default 1)")
    parser.add_argument("--knobs", help="comma list of knobs to vary (default: all of the app's)")
    parser.add_argument("--workdir", help="keep images, logs and summaries here")
    parser.add_argument("-o", "--output", required=True, help="CSV to write")
    return parser.parse_args(argv)


def choose_knobs(text, known):
    knobs = [k for k in (text or ",".join(known)).split(",") if k]
    unknown = [k for k in knobs if k not in known]
    if unknown:
        raise FormatError(f"--knobs: unknown {', '.join(unknown)} (known: {', '.join(known)})")
    return knobs


def write_rows(rows, output):
    tmp = output + ".tmp"
    with open(tmp, "w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    os.replace(tmp, output)
    print(f"wrote {output} ({len(rows)} rows)")


def main(argv=None):
    args = parse_args(argv)
    workdir = args.workdir or tempfile.mkdtemp(prefix="rtmini_sweep_")
    os.makedirs(workdir, exist_ok=True)
    if args.bake:
        return sweep_bake(args, choose_knobs(args.knobs, BAKE_KNOBS), workdir)
    knobs = choose_knobs(args.knobs, KNOBS)
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
    write_rows(rows, args.output)
    return 0


# bake: base point, knob values, and the references (see the module docstring).
BAKE_BASE = {"viewpoints": 200, "iterations": 3, "shadow-samples": 16, "gather-rays": 0,
             "bvh": "lbvh", "lookup": "kdtree"}
BAKE_KNOBS = {
    "viewpoints": [20, 50, 100, 200, 500, 1000, 2000],
    "iterations": [0, 1, 2, 3, 4, 6],
    "shadow-samples": [1, 4, 16, 64, 256],
    "gather-rays": [0, 4, 16, 64],
    "bvh": ["lbvh", "sah"],
    "lookup": ["kdtree", "sf"],
}
BAKE_REFERENCE = {"viewpoints": 700, "iterations": 8, "shadow-samples": 1024, "bvh": "sah",
                  "seed": 987654321}
BAKE_GATHER_REFERENCE_RAYS = 256
BAKE_METRICS = ("rmse", "rel_mse", "mean_abs", "view_dependent_rmse", "view_independent_rmse")


def bake_point(args, settings, reference, workdir, tag, binary, extra=(), stored=False):
    """A timed run and an error run of one bake setting: (seconds, total seconds, RSS, errors)."""
    base_cmd = [binary, args.scene] + flags(settings) + list(extra)
    seconds, total, rss = float("inf"), float("inf"), 0
    for _ in range(args.repeat):  # the fastest of the timed runs: the machine may be shared
        timed, run_rss = run_command("bake", base_cmd + ["-o", os.path.join(workdir, f"{tag}.bs")],
                                     args.scene, workdir, tag)
        phases = timed["phases"]
        seconds = min(seconds, phases.get("base", 0.0) + phases.get("iterate", 0.0))
        total = min(total, phases.get("total", 0.0))
        rss = max(rss, run_rss)
    checked, _ = run_command("bake", base_cmd + ["-o", os.path.join(workdir, f"{tag}_err.bs"),
                                                 "--reference", reference],
                             args.scene, workdir, f"{tag}_err")
    for path in (f"{tag}.bs", f"{tag}_err.bs"):
        os.remove(os.path.join(workdir, path))  # maps grow to 100s of MB; only the errors count
    errors = checked.get("errors", {})
    if stored:  # same N as the reference: the stored colours, viewpoint by viewpoint
        errors = errors.get("stored", {})
    missing = [m for m in BAKE_METRICS if errors.get(m) is None]
    if missing:
        raise FormatError(f"{tag}: the bake summary has no error {', '.join(missing)}")
    return seconds, total, rss, errors


def sweep_bake(args, knobs, workdir):
    scene_name = os.path.splitext(os.path.basename(args.scene))[0]
    ref_bin = args.bake_double or args.bake
    references = {}

    def reference(gather=False):
        """The reference map: traced, or a bake with many gather rays (made on first use)."""
        if gather not in references:
            tag = "reference_gather" if gather else "reference"
            settings = dict(BAKE_BASE, **BAKE_REFERENCE)
            extra = ["--trace-reference"]
            if gather:
                settings["gather-rays"] = BAKE_GATHER_REFERENCE_RAYS
                extra = []
            else:
                settings.pop("gather-rays")
            path = os.path.join(workdir, f"{tag}.bs")
            print(f"sweep: {tag} {settings} with {ref_bin}", file=sys.stderr)
            run_command("bake", [ref_bin, args.scene] + flags(settings) + extra + ["-o", path],
                        args.scene, workdir, tag)
            references[gather] = path
        return references[gather]

    points = [("base", BAKE_BASE["viewpoints"], "float", BAKE_BASE)]
    for knob in knobs:
        for value in BAKE_KNOBS[knob]:
            settings = dict(BAKE_BASE, **{knob: value})
            if settings != BAKE_BASE or knob == "gather-rays":
                points.append((knob, value, "float", settings))
    if args.bake_double:
        points.append(("precision", "double", "double", BAKE_BASE))
        # The float build's traced reference against the double one, colour by colour: the
        # rounding error alone.
        traced = dict(BAKE_BASE, **BAKE_REFERENCE)
        traced.pop("gather-rays")
        points.append(("traced-reference", "float", "float", traced))
    rows = []
    for knob, value, precision, settings in points:
        binary = args.bake_double if precision == "double" else args.bake
        gather = knob == "gather-rays"
        ref = reference(gather)
        tag = f"{knob}_{value}_{precision}"
        traced = knob == "traced-reference"
        extra = ["--trace-reference"] if traced else []
        seconds, total, rss, errors = bake_point(args, settings, ref, workdir, tag, binary, extra,
                                                 stored=traced)
        suffix = f"_vs_gather{BAKE_GATHER_REFERENCE_RAYS}" if gather else ""
        for name in BAKE_METRICS:
            rows.append({"app": "bake", "scene": scene_name, "knob": knob, "value": value,
                         "precision": precision, "time_s": f"{seconds:.6g}", "memory_bytes": rss,
                         "error_name": name + suffix, "error": f"{max(errors[name], 0.0):.6g}",
                         "total_s": f"{total:.6g}", "settings": " ".join(flags(settings)),
                         "reference": os.path.basename(ref)})
        print(f"sweep: {tag:28s} {seconds:8.3f} s  rmse{suffix} {errors['rmse']:.5g}",
              file=sys.stderr)
    write_rows(rows, args.output)
    return 0


if __name__ == "__main__":
    sys.exit(cli.run(main))
