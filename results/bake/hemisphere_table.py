#!/usr/bin/env python3
"""Tables of results/bake/run_hemisphere.sh from its raw folder (summaries, /usr/bin/time, sizes).

Usage: hemisphere_table.py RAW_DIR   (writes RAW_DIR/hemisphere.csv, prints Markdown)
"""
import csv
import glob
import json
import os
import re
import statistics
import sys

raw = sys.argv[1]
sizes = {}
for line in open(os.path.join(raw, "file_bytes.txt")):
    name, size = line.split()
    sizes[name] = int(size)


def load(path):
    return json.load(open(path))


def median_range(values, fmt):
    return f"{fmt.format(statistics.median(values))} ({fmt.format(min(values))}-{fmt.format(max(values))})"


rows = []
for scene in ("cornell_box", "bunny_room"):
    tags = sorted({re.sub(r"_rep\d+\.json$", "", os.path.basename(p))
                   for p in glob.glob(os.path.join(raw, f"{scene}_*_n*_rep*.json"))},
                  key=lambda t: (int(t.rsplit("_n", 1)[1]), "hemisphere" in t))
    for tag in tags:
        reps = [load(p) for p in sorted(glob.glob(os.path.join(raw, f"{tag}_rep*.json")))]
        bake_s = [r["phases"]["base"] + r["phases"]["map"] + r["phases"]["halo"] +
                  r["phases"]["iterate"] for r in reps]
        rss = [max(r["scene"]["peak_rss_bytes_per_rank"]) / 2**20 for r in reps]
        first = reps[0]
        trace = load(os.path.join(raw, f"{tag}_vs_trace.json"))["errors"]
        image = load(os.path.join(raw, f"{tag}_render.json"))["errors"]
        rows.append({
            "scene": scene,
            "directions": first["parameters"]["directions"],
            "N": first["parameters"]["viewpoints"],
            "stored": first["parameters"]["stored_viewpoints"],
            "colours": first["scene"]["colors"],
            "map_MB": first["scene"]["colors"] * 12 / 1e6,
            "bsb_MB": sizes[f"{tag}.bsb"] / 1e6,
            "bs_MB": sizes[f"{tag}.bs"] / 1e6,
            "rays": first["scene"]["rays_traced"],
            "bake_s": bake_s,
            "rss_MiB": rss,
            "colour_rmse_vd": trace["view_dependent_rmse"],
            "image_rmse": image["rmse"],
            "image_psnr": image["psnr"],
            "reps": len(reps),
        })

with open(os.path.join(raw, "hemisphere.csv"), "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["scene", "directions", "N", "stored", "colours", "map_MB", "bsb_MB", "bs_MB",
                "rays", "bake_s_median", "bake_s_min", "bake_s_max", "peak_rss_MiB_median",
                "colour_rmse_view_dependent", "image_rmse", "image_psnr_db"])
    for r in rows:
        w.writerow([r["scene"], r["directions"], r["N"], r["stored"], r["colours"],
                    f'{r["map_MB"]:.3f}', f'{r["bsb_MB"]:.3f}', f'{r["bs_MB"]:.3f}',
                    int(r["rays"]), f'{statistics.median(r["bake_s"]):.3f}',
                    f'{min(r["bake_s"]):.3f}', f'{max(r["bake_s"]):.3f}',
                    f'{statistics.median(r["rss_MiB"]):.1f}', f'{r["colour_rmse_vd"]:.5f}',
                    f'{r["image_rmse"]:.6f}', f'{r["image_psnr"]:.2f}'])

print("| scene | directions | N (stored) | colours | map MB | .bsb MB | rays | bake s, median (range) "
      "| peak RSS MiB | colour RMSE vs traced | image RMSE vs dense | PSNR dB |")
print("|---|---|---|---:|---:|---:|---:|---|---:|---:|---:|---:|")
for r in rows:
    print(f'| {r["scene"]} | {r["directions"]} | {r["N"]} ({r["stored"]}) | {r["colours"]:,} | '
          f'{r["map_MB"]:.2f} | {r["bsb_MB"]:.2f} | {int(r["rays"]):,} | '
          f'{median_range(r["bake_s"], "{:.2f}")} | {statistics.median(r["rss_MiB"]):.0f} | '
          f'{r["colour_rmse_vd"]:.4f} | {r["image_rmse"]:.5f} | {r["image_psnr"]:.1f} |')

print()
print("| scene | hemisphere N vs sphere N | colour RMSE (view-dependent) | colour mean abs | "
      "image RMSE | PSNR dB |")
print("|---|---|---:|---:|---:|---:|")
for scene in ("cornell_box", "bunny_room"):
    for p in glob.glob(os.path.join(raw, f"{scene}_hemi_vs_sphere_n*[0-9].json")):
        n = re.search(r"_n(\d+)\.json$", p).group(1)
        e = load(p)["errors"]
        im = load(p.replace(".json", "_render.json"))["errors"]
        print(f'| {scene} | N = {n} | {e["view_dependent_rmse"]:.4f} | {e["mean_abs"]:.5f} | '
              f'{im["rmse"]:.6f} | {im["psnr"]:.1f} |')
