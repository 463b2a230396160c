#!/bin/bash
# Hemisphere maps (`bake --directions hemisphere`, issue 19) against today's full-sphere maps:
# memory (colours, .bsb bytes, peak RSS), bake time and rays, and accuracy at the same N and at
# the same memory (hemisphere 2N vs sphere N), on cornell_box and bunny_room.
#   - per-colour error: every map read along the directions of a traced reference
#     (`--trace-reference`, the map the bake converges to; other seed, more shadow samples) with
#     the bake's own lookup (`--reference`, errors.view_dependent_rmse), and the hemisphere map
#     read along the full-sphere map of the same N (the difference the layout alone makes);
#   - image error: `bake render` of every map against the render of a dense sphere map (4N), and
#     the hemisphere render against the sphere render of the same N.
# Timings: REPS interleaved repetitions (median and range in the table). Raw logs, summaries and
# the CSV go to OUT (default results/bake/raw_hemisphere); the Markdown table to stdout.
# Usage: results/bake/run_hemisphere.sh BUILD_DIR [OUT_DIR]   (env: REPS, default 5)
set -euo pipefail
build=$(cd "${1:?usage: run_hemisphere.sh BUILD_DIR [OUT_DIR]}" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${2:-$here/raw_hemisphere}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bake=$build/miniapps/bake/bake
gen=$build/inputs/rtmini-gen-inputs
reps=${REPS:-5}
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OMP_PROC_BIND=false

# measure NAME INPUT N K NREF "CAMERA FLAGS": one scene.
measure() {
  local name=$1 input=$2 n=$3 k=$4 nref=$5 camera=$6
  local size=(--width 320 --height 240 --spp 4) common=(--iterations "$k" --shadow-samples 16)
  # The traced reference (per-colour truth) and the dense sphere map (image truth).
  "$bake" "$input" --trace-reference -o "$work/${name}_ref.bs" --viewpoints "$nref" \
    --iterations "$k" --shadow-samples 256 --seed 99 >"$out/${name}_trace_reference.log"
  "$bake" "$input" -o "$work/${name}_dense.bsb" --viewpoints $((4 * n)) "${common[@]}" \
    --summary "$out/${name}_dense.json" >"$out/${name}_dense.log"
  # shellcheck disable=SC2086
  "$bake" render "$work/${name}_dense.bsb" -o "$work/${name}_dense.exr" $camera "${size[@]}" \
    >"$out/${name}_dense_render.log"
  local configs=("sphere $n" "hemisphere $n" "hemisphere $((2 * n))" "sphere $((2 * n))")
  local rep c dirs vn tag
  for rep in $(seq 1 "$reps"); do  # interleaved: every layout sees the same machine load
    for c in "${configs[@]}"; do
      read -r dirs vn <<<"$c"
      tag=${name}_${dirs}_n${vn}
      /usr/bin/time -f "%e s wall, %M KB max RSS" -o "$out/${tag}_rep$rep.time" \
        "$bake" "$input" -o "$work/$tag.bsb" --viewpoints "$vn" --directions "$dirs" \
        "${common[@]}" --summary "$out/${tag}_rep$rep.json" >"$out/${tag}_rep$rep.log"
    done
  done
  for c in "${configs[@]}"; do
    read -r dirs vn <<<"$c"
    tag=${name}_${dirs}_n${vn}
    # Same bake again, text form, judged against the traced reference.
    "$bake" "$input" -o "$work/$tag.bs" --viewpoints "$vn" --directions "$dirs" "${common[@]}" \
      --reference "$work/${name}_ref.bs" --summary "$out/${tag}_vs_trace.json" \
      >"$out/${tag}_vs_trace.log"
    # shellcheck disable=SC2086
    "$bake" render "$work/$tag.bsb" -o "$work/$tag.exr" $camera "${size[@]}" \
      --reference "$work/${name}_dense.exr" --summary "$out/${tag}_render.json" \
      >"$out/${tag}_render.log"
  done
  # The layout alone: hemisphere N against sphere N (per colour and image).
  "$bake" "$input" -o "$work/x.bs" --viewpoints "$n" --directions hemisphere "${common[@]}" \
    --reference "$work/${name}_sphere_n$n.bs" --summary "$out/${name}_hemi_vs_sphere_n$n.json" \
    >"$out/${name}_hemi_vs_sphere_n$n.log"
  # shellcheck disable=SC2086
  "$bake" render "$work/${name}_hemisphere_n$n.bsb" -o "$work/x.exr" $camera "${size[@]}" \
    --reference "$work/${name}_sphere_n$n.exr" --summary "$out/${name}_hemi_vs_sphere_n${n}_render.json" \
    >"$out/${name}_hemi_vs_sphere_n${n}_render.log"
  for c in "${configs[@]}"; do
    read -r dirs vn <<<"$c"
    stat -c "%n %s" "$work/${name}_${dirs}_n$vn.bsb" "$work/${name}_${dirs}_n$vn.bs" |
      sed "s|$work/||" >>"$out/file_bytes.txt"
  done
}

: >"$out/file_bytes.txt"
measure cornell_box "$root/inputs/cornell/cornell_box.bs" 100 3 1000 \
  "--camera-pos 0.9,1.1,2.4 --look-at -0.1,0.7,-0.2 --fov 35"
"$gen" bunny_room --scene "$root/inputs/meshes/stanford-bunny.obj" -o "$work/bunny_room.bs" >/dev/null
measure bunny_room "$work/bunny_room.bs" 100 2 40 ""
python3 "$here/hemisphere_table.py" "$out"
