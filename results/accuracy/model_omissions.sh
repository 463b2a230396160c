#!/bin/bash
# The error of each physical effect the apps leave out or approximate (issue 7, "Document the
# model"): render a scene with the effect left out (the app's default or cheaper setting) and
# with it included, and compare (RMSE, relative MSE, PSNR, SSIM from --reference). Every
# reference is rendered twice with different seeds; the RMSE between the two copies is the
# noise floor printed next to each omission error. Writes model_omissions.csv and
# model_omissions.md to OUT (default: this folder) and the run logs and JSON summaries to
# OUT/raw_model/. Images live in a temporary folder and are deleted.
# Usage: results/accuracy/model_omissions.sh BUILD_DIR [OUT_DIR]
# Environment: SPP (default 64) pixel samples; PARTS (default "sketchtrace lowres bake ao"):
# a subset re-runs only those parts and appends their rows to the existing CSV files.
set -euo pipefail
build=$(cd "${1:?usage: model_omissions.sh BUILD_DIR [OUT_DIR]}" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${2:-$here}
mkdir -p "$out/raw_model"
out=$(cd "$out" && pwd)
raw=$out/raw_model
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sketch=$build/miniapps/sketchtrace/sketchtrace
bake=$build/miniapps/bake/bake
py=/usr/bin/python3
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OMP_PROC_BIND=false
spp=${SPP:-64}
size=(--width 320 --height 240)
parts=${PARTS:-sketchtrace lowres bake ao}
csv=$out/model_omissions.csv
ao_csv=$out/model_omissions_ao.csv
if [ "$parts" = "sketchtrace lowres bake ao" ] || [ ! -f "$csv" ]; then
  echo "app,scene,omission,test,reference,rmse,rel_mse,psnr_db,ssim,noise_rmse,noise_rel_mse,noise_ssim,test_s" >"$csv"
  echo "test,reference,vertices,rms_diff,mean_diff,max_abs_diff,mean_ao_ref" >"$ao_csv"
fi
start=$SECONDS

# st ID REF SCENE ARGS...: sketchtrace SCENE into ID.exr, compared with REF.exr unless REF is -.
st() {
  local id=$1 ref=$2 scene=$3
  shift 3
  local cmp=()
  [ "$ref" = - ] || cmp=(--reference "$work/$ref.exr")
  echo "sketchtrace $scene ${size[*]} --spp $spp $* ${cmp[*]}" >"$raw/$id.log"
  "$sketch" "$scene" -o "$work/$id.exr" "${size[@]}" --spp "$spp" "$@" "${cmp[@]}" \
    --summary "$raw/$id.json" >>"$raw/$id.log" 2>&1
}

# br ID MAP VIEW REF: bake render MAP through the camera of VIEW.toml into ID.exr against REF.exr.
br() {
  echo "bake render $2 --scene $3 ${size[*]} --spp 16 --reference $4.exr" >"$raw/$1.log"
  "$bake" render "$2" --scene "$3" "${size[@]}" --spp 16 -o "$work/$1.exr" \
    --reference "$work/$4.exr" --summary "$raw/$1.json" >>"$raw/$1.log" 2>&1
}

# row APP SCENE OMISSION TEST REF NOISE: a CSV row from TEST.json's errors and NOISE.json's RMSE
# (NOISE = the reference's second-seed copy, itself compared with REF; - for none): its RMSE,
# relative MSE and SSIM are the noise floor of each metric.
row() {
  $py - "$raw" "$@" >>"$csv" <<'PY'
import csv, json, sys
raw, app, scene, omission, test, ref, noise = sys.argv[1:8]
t = json.load(open(f"{raw}/{test}.json"))
e = t["errors"]
n = json.load(open(f"{raw}/{noise}.json"))["errors"] if noise != "-" else {}
nan = float("nan")
secs = t["phases"].get("render", t["phases"]["total"])
csv.writer(sys.stdout, lineterminator="\n").writerow(
    [app, scene, omission, test, ref, f'{e["rmse"]:.5f}', f'{e["rel_mse"]:.5f}', f'{e["psnr"]:.2f}',
     f'{e["ssim"]:.4f}', f'{n.get("rmse", nan):.5f}', f'{n.get("rel_mse", nan):.5f}',
     f'{n.get("ssim", nan):.4f}', f"{secs:.2f}"])
PY
}

# A sketchtrace scene of a mesh alone with a camera (as results/bake_render/run_accuracy.sh).
view_toml() {
  printf '[camera]\nposition = [%s]\nlook_at = [%s]\nup = [0, 1, 0]\nfov_deg = %s\n[[meshes]]\nfile = "%s"\n' \
    "$3" "$4" "$5" "$2" >"$work/$1.toml"
}

ts=$root/inputs/two_spheres/two_spheres.toml
wt=$root/inputs/watchtower/watchtower.toml
sp=$root/inputs/spheres/spheres.toml
gi=(--indirect on --bounces 12 --ambient "0,0,0")
# --- sketchtrace -----------------------------------------------------------------------------
# Diffuse interreflection, its ambient stand-in and bounce truncation: reference = path traced
# diffuse interreflection (--indirect on) with 12 bounces and no ambient term.
part_sketchtrace() {
  for s in ts:"$ts":0.03 wt:"$wt":0.06 sp:"$sp":0.04; do
    id=${s%%:*} rest=${s#*:}
    scene=${rest%:*} amb=${rest##*:}
    st "${id}_gi" - "$scene" "${gi[@]}" --seed 1
    st "${id}_gi_s2" "${id}_gi" "$scene" "${gi[@]}" --seed 2
    st "${id}_direct" "${id}_gi" "$scene" --indirect off --bounces 12 --ambient 0,0,0 --seed 1
    st "${id}_ambient" "${id}_gi" "$scene" --indirect off --bounces 12 --ambient "$amb,$amb,$amb" --seed 1
    st "${id}_gi_b3" "${id}_gi" "$scene" --indirect on --bounces 3 --ambient 0,0,0 --seed 1
    name=$(basename "$scene" .toml)
    row sketchtrace "$name" "no diffuse interreflection (--indirect off; ambient 0)" "${id}_direct" "${id}_gi" "${id}_gi_s2"
    row sketchtrace "$name" "ambient $amb instead of interreflection (scene default)" "${id}_ambient" "${id}_gi" "${id}_gi_s2"
    row sketchtrace "$name" "interreflection truncated at 3 bounces (vs 12)" "${id}_gi_b3" "${id}_gi" "${id}_gi_s2"
  done

  # Bounce truncation of specular paths only (the default model, --indirect off): spheres has a
  # mirror, a glass and a glossy sphere; default 4 bounces, reference 12.
  st sp_b12 - "$sp" --bounces 12 --seed 1
  st sp_b12_s2 sp_b12 "$sp" --bounces 12 --seed 2
  st sp_b4 sp_b12 "$sp" --bounces 4 --seed 1
  row sketchtrace spheres "specular bounces truncated at 4 (default; vs 12)" sp_b4 sp_b12 sp_b12_s2

  # Geometry and shadows in the default model (scene settings): tessellated spheres (level 5,
  # the default, vs 7), hard shadows (--soft-shadows off) and flat normals (--smooth off).
  st ts_sub7 - "$ts" --sphere-subdivisions 7 --seed 1
  st ts_sub7_s2 ts_sub7 "$ts" --sphere-subdivisions 7 --seed 2
  st ts_def ts_sub7 "$ts" --seed 1
  st ts_def_s2 ts_def "$ts" --seed 2
  st ts_sub3 ts_sub7 "$ts" --sphere-subdivisions 3 --seed 1
  st ts_hard ts_def "$ts" --soft-shadows off --seed 1
  row sketchtrace two_spheres "tessellated spheres, level 5 (default; vs 7)" ts_def ts_sub7 ts_sub7_s2
  row sketchtrace two_spheres "tessellated spheres, level 3 (vs 7)" ts_sub3 ts_sub7 ts_sub7_s2
  row sketchtrace two_spheres "hard shadows (light centre; vs soft)" ts_hard ts_def ts_def_s2
  st wt_def - "$wt" --seed 1
  st wt_def_s2 wt_def "$wt" --seed 2
  st wt_flat wt_def "$wt" --smooth off --seed 1
  st wt_hard wt_def "$wt" --soft-shadows off --seed 1
  row sketchtrace watchtower "flat normals (--smooth off; vs smooth)" wt_flat wt_def wt_def_s2
  row sketchtrace watchtower "hard shadows (light centre; vs soft)" wt_hard wt_def wt_def_s2
}

# --- interreflection at 80x60 with 16x the samples per pixel (the same cost per render) ---------
# On two_spheres the path-traced caustics of the mirror spheres (floor -> sphere -> light) leave
# fireflies in the interreflection reference that hide the omission at 320x240; the omission is
# low-frequency, so a coarser image with more samples per pixel resolves it.
part_lowres() {
  local size=(--width 80 --height 60) spp=$((spp * 16))
  st tslo_gi - "$ts" "${gi[@]}" --seed 1
  st tslo_gi_s2 tslo_gi "$ts" "${gi[@]}" --seed 2
  st tslo_direct tslo_gi "$ts" --indirect off --bounces 12 --ambient "0,0,0" --seed 1
  st tslo_ambient tslo_gi "$ts" --indirect off --bounces 12 --ambient "0.03,0.03,0.03" --seed 1
  row sketchtrace "two_spheres 80x60" "no diffuse interreflection (--indirect off; ambient 0)" tslo_direct tslo_gi tslo_gi_s2
  row sketchtrace "two_spheres 80x60" "ambient 0.03 instead of interreflection (scene default)" tslo_ambient tslo_gi tslo_gi_s2
  # The gridded Cornell box (boxes view): its half-mirror boxes do the same.
  local cb=$root/inputs/cornell_big/cornell_big_raw.bs g
  local flat=(--smooth off --shadow-samples 16 --ambient "0,0,0")
  view_toml cblo_boxes "$cb" "0.9, 1.1, 2.4" "-0.1, 0.7, -0.2" 35
  st cblo_gi - "$work/cblo_boxes.toml" "${flat[@]}" --indirect on --bounces 12 --seed 1
  st cblo_gi_s2 cblo_gi "$work/cblo_boxes.toml" "${flat[@]}" --indirect on --bounces 12 --seed 2
  st cblo_direct cblo_gi "$work/cblo_boxes.toml" "${flat[@]}" --indirect off --bounces 12 --seed 1
  row sketchtrace "cornell_big_raw 80x60" "no diffuse interreflection (--indirect off; ambient 0)" cblo_direct cblo_gi cblo_gi_s2
  for g in 0 64; do
    echo "bake $cb --viewpoints 100 --iterations 4 --shadow-samples 16 --gather-rays $g" >"$raw/bakelo_g$g.log"
    "$bake" "$cb" -o "$work/cblo_g$g.bs" --viewpoints 100 --iterations 4 --shadow-samples 16 \
      --gather-rays "$g" --summary "$raw/bakelo_g$g.json" >>"$raw/bakelo_g$g.log" 2>&1
    br "cblo_g${g}_vs_gi" "$work/cblo_g$g.bs" "$work/cblo_boxes.toml" cblo_gi
    row bake "cornell_big_raw 80x60" "gather rays $g, K = 4 (vs sketchtrace, interreflection)" "cblo_g${g}_vs_gi" cblo_gi cblo_gi_s2
  done
}

# --- bake (map mode) against sketchtrace, on the gridded Cornell box -------------------------
# References: sketchtrace with the bake's model (direct + K = 4 mirror bounces, flat normals)
# and with diffuse interreflection (12 bounces). Bakes: N = 100, K = 4, 16 shadow samples.
part_bake() {
  cb=$root/inputs/cornell_big/cornell_big_raw.bs
  # The "boxes" view of results/bake_render (the light and the ceiling are out of view).
  view_toml cb_boxes "$cb" "0.9, 1.1, 2.4" "-0.1, 0.7, -0.2" 35
  cbv=$work/cb_boxes.toml
  flat=(--smooth off --shadow-samples 16 --ambient "0,0,0")
  st cb_gi - "$cbv" "${flat[@]}" --indirect on --bounces 12 --seed 1
  st cb_gi_s2 cb_gi "$cbv" "${flat[@]}" --indirect on --bounces 12 --seed 2
  st cb_direct cb_gi "$cbv" "${flat[@]}" --indirect off --bounces 12 --seed 1
  st cb_gi_b4 cb_gi "$cbv" "${flat[@]}" --indirect on --bounces 4 --seed 1
  st cb_k4 - "$cbv" "${flat[@]}" --indirect off --bounces 4 --seed 1
  st cb_k4_s2 cb_k4 "$cbv" "${flat[@]}" --indirect off --bounces 4 --seed 2
  row sketchtrace cornell_big_raw "no diffuse interreflection (--indirect off; ambient 0)" cb_direct cb_gi cb_gi_s2
  row sketchtrace cornell_big_raw "interreflection truncated at 4 bounces (vs 12)" cb_gi_b4 cb_gi cb_gi_s2
  for g in 0 64 256; do
    echo "bake $cb --viewpoints 100 --iterations 4 --shadow-samples 16 --gather-rays $g" >"$raw/bake_g$g.log"
    "$bake" "$cb" -o "$work/cb_g$g.bs" --viewpoints 100 --iterations 4 --shadow-samples 16 \
      --gather-rays "$g" --summary "$raw/bake_g$g.json" >>"$raw/bake_g$g.log" 2>&1
    br "cb_g${g}_vs_gi" "$work/cb_g$g.bs" "$cbv" cb_gi
    br "cb_g${g}_vs_k4" "$work/cb_g$g.bs" "$cbv" cb_k4
    row bake cornell_big_raw "gather rays $g, K = 4 (vs sketchtrace, interreflection)" "cb_g${g}_vs_gi" cb_gi cb_gi_s2
    row bake cornell_big_raw "gather rays $g, K = 4 (vs sketchtrace, bake's model)" "cb_g${g}_vs_k4" cb_k4 cb_k4_s2
  done

  # Vertices on a concave edge (every wall grid's border lies on the next wall's plane): the same
  # bake with every face's corners moved 0.1 % towards its centroid (no vertex on another face).
  $py "$here/bs_split_creases.py" "$cb" "$work/cb_inset.bs" --by face --inset 1e-3 >"$raw/cb_inset.log"
  echo "bake cb_inset.bs --viewpoints 100 --iterations 4 --shadow-samples 16" >"$raw/bake_cb_inset.log"
  "$bake" "$work/cb_inset.bs" -o "$work/cb_inset_baked.bs" --viewpoints 100 --iterations 4 \
    --shadow-samples 16 --summary "$raw/bake_cb_inset.json" >>"$raw/bake_cb_inset.log" 2>&1
  br cb_inset_vs_k4 "$work/cb_inset_baked.bs" "$cbv" cb_k4
  row bake cornell_big_raw "edge vertices moved off the adjacent walls (inset 0.1 %), gather 0 (vs bake's model)" cb_inset_vs_k4 cb_k4 cb_k4_s2

  # The same on the 72-vertex Cornell box: every wall is one quad whose 4 corners all lie on
  # concave edges, and the boxes' faces have their own vertices.
  cx=$root/inputs/cornell/cornell_box.bs
  view_toml cx_boxes "$cx" "0.9, 1.1, 2.4" "-0.1, 0.7, -0.2" 35
  st cx_k4 - "$work/cx_boxes.toml" "${flat[@]}" --indirect off --bounces 4 --seed 1
  st cx_k4_s2 cx_k4 "$work/cx_boxes.toml" "${flat[@]}" --indirect off --bounces 4 --seed 2
  $py "$here/bs_split_creases.py" "$cx" "$work/cx_inset.bs" --by face --inset 1e-3 >"$raw/cx_inset.log"
  cp "$cx" "$work/cx.bs"
  for v in cx cx_inset; do
    echo "bake $v.bs --viewpoints 100 --iterations 4 --shadow-samples 16" >"$raw/bake_$v.log"
    "$bake" "$work/$v.bs" -o "$work/${v}_baked.bs" --viewpoints 100 --iterations 4 \
      --shadow-samples 16 --summary "$raw/bake_$v.json" >>"$raw/bake_$v.log" 2>&1
    br "${v}_vs_k4" "$work/${v}_baked.bs" "$work/cx_boxes.toml" cx_k4
  done
  row bake cornell_box "as bundled, gather 0 (vs bake's model)" cx_vs_k4 cx_k4 cx_k4_s2
  row bake cornell_box "corners moved off the adjacent walls (inset 0.1 %) (vs bake's model)" cx_inset_vs_k4 cx_k4 cx_k4_s2

  # Per-vertex material and normal averages: the cube (8 corners shared by an emissive top and
  # reflective sides) as bundled, and split so that no vertex is shared across a crease.
  cp "$root/inputs/cube/cube.bs" "$work/cube.bs"
  $py "$here/bs_split_creases.py" "$work/cube.bs" "$work/cube_split.bs" --by material+normal >"$raw/cube_split.log"
  $py "$here/bs_split_creases.py" "$work/cube.bs" "$work/cube_inset.bs" --by face --inset 1e-3 >"$raw/cube_inset.log"
  # Camera inside the box (its faces are wound inwards; the light is the top face, emitting down).
  view_toml cube "$work/cube.bs" "0, -0.3, 0.95" "0, 0.1, -1" 75
  st cube_ref - "$work/cube.toml" "${flat[@]}" --indirect off --bounces 4 --seed 1
  st cube_ref_s2 cube_ref "$work/cube.toml" "${flat[@]}" --indirect off --bounces 4 --seed 2
  for v in cube cube_split cube_inset; do
    echo "bake $v.bs --viewpoints 100 --iterations 4 --shadow-samples 16" >"$raw/bake_$v.log"
    "$bake" "$work/$v.bs" -o "$work/${v}_baked.bs" --viewpoints 100 --iterations 4 \
      --shadow-samples 16 --summary "$raw/bake_$v.json" >>"$raw/bake_$v.log" 2>&1
    br "${v}_render" "$work/${v}_baked.bs" "$work/cube.toml" cube_ref
  done
  row bake cube "vertex material + normal averages (bundled, shared corners)" cube_render cube_ref cube_ref_s2
  row bake cube "split at creases (no shared corners)" cube_split_render cube_ref cube_ref_s2
  row bake cube "split per face and inset 0.1 % (no vertex on an edge)" cube_inset_render cube_ref cube_ref_s2
}

# --- bake --mode ao: Spot on its virtual ground plane ----------------------------------------
part_ao() {
  spot=$root/inputs/watchtower/spot.obj
  ao() {
    echo "bake --mode ao $spot $*" >"$raw/ao_$1.log"
    local id=$1
    shift
    "$bake" "$spot" --mode ao -o "$work/ao_$id.bin" --rays 256 "$@" \
      --summary "$raw/ao_$id.json" >>"$raw/ao_$id.log" 2>&1
  }
  ao ref --seed 1
  ao s2 --seed 2
  ao d0001 --seed 1 -d 0.001
  ao m100 --seed 1 -m 100
  for t in s2 d0001 m100; do
    echo "ao_$t,ao_ref,$($py "$here/ao_compare.py" "$work/ao_$t.bin" "$work/ao_ref.bin")" >>"$ao_csv"
  done
}

for part in $parts; do
  "part_$part"
done
echo "parts '$parts': $((SECONDS - start)) s, load average $(cut -d' ' -f1-3 /proc/loadavg)" |
  tee -a "$raw/total_time.log"
$py - "$csv" "$ao_csv" >"$out/model_omissions.md" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("| app | scene | left out / approximated | RMSE (floor) | rel. MSE (floor) | PSNR dB | "
      "SSIM (floor) | render s |")
print("|---|---|---|---:|---:|---:|---:|---:|")
for r in rows:
    print(f'| {r["app"]} | {r["scene"]} | {r["omission"]} | {r["rmse"]} ({r["noise_rmse"]}) | '
          f'{r["rel_mse"]} ({r["noise_rel_mse"]}) | {r["psnr_db"]} | {r["ssim"]} ({r["noise_ssim"]}) | '
          f'{r["test_s"]} |')
print()
print("| AO test | vs | vertices | RMS diff | mean diff | max abs diff | mean AO |")
print("|---|---|---:|---:|---:|---:|---:|")
for r in csv.DictReader(open(sys.argv[2])):
    print(f'| {r["test"]} | {r["reference"]} | {r["vertices"]} | {r["rms_diff"]} | '
          f'{r["mean_diff"]} | {r["max_abs_diff"]} | {r["mean_ao_ref"]} |')
PY
cat "$out/model_omissions.md"
