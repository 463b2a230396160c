#!/bin/bash
# Accuracy of baked maps against sketchtrace (issue 9): bake a scene with N viewpoints and K
# iterations, render the map with `bake render`, and compare with sketchtrace's ray-traced image
# of the same scene, camera and light transport (emission + direct light with 16 stratified
# shadow samples + K mirror bounces, no diffuse interreflection; README.md lists what differs).
# Writes accuracy.csv, accuracy.md and the PNGs shown in README.md into OUT (default: here).
# Usage: results/bake_render/run_accuracy.sh BUILD_DIR [OUT_DIR]
set -euo pipefail
build=$(cd "${1:?usage: run_accuracy.sh BUILD_DIR [OUT_DIR]}" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${2:-$here}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bake=$build/miniapps/bake/bake
sketch=$build/miniapps/sketchtrace/sketchtrace
gen=$build/inputs/rtmini-gen-inputs
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OMP_PROC_BIND=false
size=(--width 320 --height 240)
shadow=16
csv=$out/accuracy.csv
echo "scene,vertices,view,N,K,bake_compute_s,bake_total_s,map_bytes,rmse,rel_mse,psnr_db,ssim" >"$csv"

# scene_toml NAME INPUT POSITION LOOK_AT FOV: a sketchtrace scene of the mesh alone + camera.
scene_toml() {
  printf '[camera]\nposition = [%s]\nlook_at = [%s]\nup = [0, 1, 0]\nfov_deg = %s\n[[meshes]]\nfile = "%s"\n' \
    "$3" "$4" "$5" "$2" >"$work/$1.toml"
}

# measure NAME INPUT "N..." "K..." VIEW...: one sketchtrace reference per K and view, one bake
# per (N, K), one `bake render` per (N, K, view); rows appended to the CSV.
measure() {
  local name=$1 input=$2 ns=$3 ks=$4
  shift 4
  local views=("$@") k n view map
  for k in $ks; do
    for view in "${views[@]}"; do
      "$sketch" "$work/${name}_$view.toml" -o "$work/${name}_${view}_ref_k$k.png" "${size[@]}" \
        --spp 64 --shadow-samples $shadow --bounces "$k" --indirect off --soft-shadows on \
        --smooth off --seed 11 >"$work/sketch.txt"
    done
    for n in $ns; do
      map=$work/${name}_n${n}_k$k.bs
      "$bake" "$input" -o "$map" --viewpoints "$n" --iterations "$k" --shadow-samples $shadow \
        --summary "$work/bake.json" >"$work/bake.txt"
      for view in "${views[@]}"; do
        "$bake" render "$map" --scene "$work/${name}_$view.toml" "${size[@]}" --spp 16 \
          -o "$work/${name}_${view}_n${n}_k$k.png" --reference "$work/${name}_${view}_ref_k$k.png" \
          --summary "$work/render.json" >"$work/render.txt"
        python3 - "$work/bake.json" "$work/render.json" "$name" "$view" "$n" "$k" "$map" \
          >>"$csv" <<'PY'
import json, os, sys
b, r = (json.load(open(p)) for p in sys.argv[1:3])
name, view, n, k, path = sys.argv[3:8]
ph, e = b["phases"], r["errors"]
print(f'{name},{b["scene"]["vertices"]},{view},{n},{k},{ph["base"] + ph["iterate"]:.4f},'
      f'{ph["total"]:.3f},{os.path.getsize(path)},{e["rmse"]:.5f},{e["rel_mse"]:.5f},'
      f'{e["psnr"]:.2f},{e["ssim"]:.4f}')
PY
      done
      rm -f "$map"
    done
  done
}

# The Cornell box twice: the shared 72-vertex box and the 1,924-vertex gridded one. Views: the
# whole box through its open side, and a close-up of the semi-reflective boxes.
for scene in cornell/cornell_box cornell_big/cornell_big_raw; do
  name=$(basename "$scene")
  scene_toml "${name}_front" "$root/inputs/$scene.bs" "0, 1, 3.9" "0, 1, 0" 40
  scene_toml "${name}_boxes" "$root/inputs/$scene.bs" "0.9, 1.1, 2.4" "-0.1, 0.7, -0.2" 35
  measure "$name" "$root/inputs/$scene.bs" "20 100 1000" "1 2 4" front boxes
  for view in front boxes; do
    for f in ref_k4 n20_k4 n1000_k4; do cp "$work/${name}_${view}_$f.png" "$out/"; done
  done
done

# The bunny bake scene (inputs/gen_inputs.cpp): 35,959 vertices; N = 1000 would be a 2 GB map.
"$gen" bunny --scene "$root/inputs/meshes/stanford-bunny.obj" -o "$work/bunny_raw.bs" >/dev/null
scene_toml bunny_close "$work/bunny_raw.bs" "0.1, 0.17, 0.28" "-0.017, 0.1, 0" 40
measure bunny "$work/bunny_raw.bs" "20 100" "2" close
for f in ref_k2 n20_k2 n100_k2; do cp "$work/bunny_close_$f.png" "$out/"; done

python3 - "$csv" >"$out/accuracy.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| scene (vertices) | view | N | K | bake compute s | bake total s | map MB | RMSE | "
      "rel. MSE | PSNR dB | SSIM |")
print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for r in rows:
    print(f'| {r["scene"]} ({r["vertices"]}) | {r["view"]} | {r["N"]} | {r["K"]} | '
          f'{r["bake_compute_s"]} | {r["bake_total_s"]} | {int(r["map_bytes"]) / 1e6:.2f} | '
          f'{r["rmse"]} | {r["rel_mse"]} | {r["psnr_db"]} | {r["ssim"]} |')
PY
cat "$out/accuracy.md"
