#!/usr/bin/env python3
"""Tables and a figure from light_convergence.csv (light_convergence.sh): per scene and binary
the RMSE against the reference at each spp (root of the mean squared error over the seeds), the
same with the reference's own noise removed, the median render time, and the log-log slopes of
RMSE against spp and against time; the stratification splits; the bias check of the references.
Usage: light_convergence_report.py CSV OUT_PREFIX  (writes OUT_PREFIX.md and OUT_PREFIX.png)"""
import collections
import csv
import math
import statistics
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

rows = list(csv.DictReader(open(sys.argv[1])))
prefix = sys.argv[2]
groups = collections.defaultdict(list)
refs = {}
for r in rows:
    if r["binary"].endswith("reference"):
        refs[(r["scene"], r["binary"])] = float(r["rmse"])
        continue
    groups[(r["scene"], r["binary"], int(r["spp"]), int(r["shadow_samples"]))].append(r)


def slope(xs, ys):
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    mx, my = statistics.mean(lx), statistics.mean(ly)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sum((a - mx) ** 2 for a in lx)


out = []
fig, axes = plt.subplots(1, 2, figsize=(10, 4))
for ax, scene in zip(axes, ["reflected_shadow", "glass"]):
    # The reference's own noise: two AFTER references of different seeds differ by sqrt(2) sigma.
    sigma_ref = refs[(scene, "after_reference")] / math.sqrt(2)
    out.append(f"### {scene}\n")
    out.append(
        f"Reference noise (RMSE between two {scene} references / sqrt 2): {sigma_ref:.5f}. "
        f"BEFORE's reference against AFTER's: {refs[(scene, 'before_reference')]:.5f}, AFTER's "
        f"second reference against the first: {refs[(scene, 'after_reference')]:.5f} (equal "
        "within noise: both estimate the same image).\n")
    out.append("| spp | before RMSE | before denoised | before rays | after RMSE | after denoised | after rays |")
    out.append("|---:|---:|---:|---:|---:|---:|---:|")
    series = {}
    for binary in ["before", "after"]:
        pts = []
        for spp in sorted({k[2] for k in groups if k[0] == scene and k[1] == binary}):
            g = groups[(scene, binary, spp, 4)]
            mse = statistics.mean(float(r["rmse"]) ** 2 for r in g)
            secs = statistics.median(float(r["render_s"]) for r in g)
            rays = statistics.mean(float(r["rays"]) for r in g)
            den = math.sqrt(max(mse - sigma_ref**2, 0.0))
            pts.append((spp, math.sqrt(mse), den, secs, rays))
        series[binary] = pts
    for (spp, b, bd, _, br), (_, a, ad, _, ar) in zip(series["before"], series["after"]):
        out.append(f"| {spp} | {b:.5f} | {bd:.5f} | {br:.0f} | {a:.5f} | {ad:.5f} | {ar:.0f} |")
    for binary, pts in series.items():
        ok = [p for p in pts if p[2] > 0]
        s_spp = slope([p[0] for p in ok], [p[2] for p in ok])
        s_r = slope([p[4] for p in ok], [p[2] for p in ok])
        out.append(f"\n{binary}: log-log slope of denoised RMSE vs spp {s_spp:.2f}, vs rays {s_r:.2f}")
        ax.loglog([p[4] for p in pts], [p[1] for p in pts], "o-", label=f"{binary} (RMSE)")
        ax.loglog([p[4] for p in ok], [p[2] for p in ok], "x--", label=f"{binary} (ref. noise removed)")
    out.append("")
    ax.set_title(scene)
    ax.set_xlabel("rays traced (the render's work; 1..64 spp, 4 shadow samples)")
    ax.set_ylabel("RMSE vs reference")
    ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(prefix + ".png", dpi=100)

out.append("### Joint stratification (penumbra, 16 shadow rays per pixel)\n")
out.append("| spp x shadow samples | before RMSE | after RMSE |")
out.append("|---|---:|---:|")
splits = sorted({(k[2], k[3]) for k in groups if k[0] == "penumbra"}, reverse=True)
for spp, sh in splits:
    vals = []
    for binary in ["before", "after"]:
        g = groups[("penumbra", binary, spp, sh)]
        vals.append(math.sqrt(statistics.mean(float(r["rmse"]) ** 2 for r in g)))
    out.append(f"| {spp} x {sh} | {vals[0]:.5f} | {vals[1]:.5f} |")
out.append("\n### Cost: render time at 32 spp, 5 interleaved repeats\n")
out.append("| scene | before s (min, median, max) | after s (min, median, max) | after / before (min) | rays after / before |")
out.append("|---|---|---|---:|---:|")
for scene in ["reflected_shadow", "glass"]:
    cells, med, rays = [], {}, {}
    for binary in ["before", "after"]:
        g = groups.get((f"timing_{scene}", binary, 32, 4), [])
        if not g:
            break
        t = [float(r["render_s"]) for r in g]
        med[binary] = min(t)
        rays[binary] = statistics.mean(float(r["rays"]) for r in g)
        cells.append(f"{min(t):.3f}, {statistics.median(t):.3f}, {max(t):.3f}")
    if len(cells) == 2:
        out.append(f"| {scene} | {cells[0]} | {cells[1]} | {med['after'] / med['before']:.2f} | "
                   f"{rays['after'] / rays['before']:.3f} |")
open(prefix + ".md", "w").write("\n".join(out) + "\n")
print("\n".join(out))
