#!/usr/bin/env bash
# Height fields (issue 24): parallax occlusion mapping against true displacement on the
# textured cube's height-field face, seen at about 40 degrees. The reference is the face
# tessellated and displaced at level 8 (2 x 256 x 256 triangles); every other mode is
# compared with it (sketchtrace --reference: RMSE over the whole linear image) and timed
# two ways, REPEAT runs each: the render phase's wall time, and the CPU time (user + sys) of the
# whole process (load, tessellation, BVH build, render), which time-sharing with other jobs on
# a busy machine inflates far less. The noise floor is the reference rendered with another seed.
# Writes raw_surface_detail/ (logs, images) and surface_detail.csv.
# Usage: results/accuracy/surface_detail.sh [build-dir]   (env: W H SPP REPEAT THREADS)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$root/build}
app=$build/miniapps/sketchtrace/sketchtrace
scene=$root/inputs/textured_cube/textured_cube.toml
out=$root/results/accuracy/raw_surface_detail
W=${W:-240} H=${H:-180} SPP=${SPP:-8} REPEAT=${REPEAT:-3}
export OMP_NUM_THREADS=${THREADS:-1} OMP_PROC_BIND=false OMP_WAIT_POLICY=passive
mkdir -p "$out"
view=(--camera-pos 0.9,0.7,1.6 --look-at 0,0.5,0.5 --width "$W" --height "$H" --spp "$SPP"
      --shadow-samples 4)
"$app" "$scene" "${view[@]}" --displacement tessellate --displacement-level 8 \
  -o "$out/reference.exr" > "$out/reference.log"
csv=$root/results/accuracy/surface_detail.csv
echo "mode,level,triangles,render_s_median,render_s_min,render_s_max,cpu_s_median,cpu_s_min,cpu_s_max,rmse,psnr_db" > "$csv"
median_min_max() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)] "," a[1] "," a[NR]}'; }
row() {  # row MODE LEVEL ARGS...: REPEAT renders against the reference, one CSV row
  local id=$1$2
  local key=$1,$2
  shift 2
  local times=() cpu=()
  for r in $(seq 1 "$REPEAT"); do
    echo "$app $scene ${view[*]} $* --reference $out/reference.exr" > "$out/$id.r$r.log"
    local TIMEFORMAT="cpu %U %S"
    { time "$app" "$scene" "${view[@]}" "$@" --reference "$out/reference.exr" -o "$out/$id.exr" \
      >> "$out/$id.r$r.log" 2>&1; } 2>> "$out/$id.r$r.log" || true
    times+=("$(sed -n 's/.*render: \([0-9.]*\) s.*/\1/p' "$out/$id.r$r.log")")
    cpu+=("$(awk '/^cpu / {print $2 + $3}' "$out/$id.r$r.log")")
  done
  local stats cpus tris rmse psnr
  stats=$(printf '%s\n' "${times[@]}" | median_min_max)
  cpus=$(printf '%s\n' "${cpu[@]}" | median_min_max)
  tris=$(sed -n 's/.*"triangles":\([0-9]*\).*/\1/p' "$out/$id.r1.log" | head -1)
  rmse=$(sed -n 's/.*RMSE \([0-9.e+-]*\),.*/\1/p' "$out/$id.r1.log")
  psnr=$(sed -n 's/.*PSNR \([0-9.inf-]*\) dB.*/\1/p' "$out/$id.r1.log")
  echo "$key,$tris,$stats,$cpus,$rmse,$psnr" >> "$csv"
}
row noise_floor 8 --displacement tessellate --displacement-level 8 --seed 2
row parallax "" --displacement parallax
row off "" --displacement off
for level in 3 4 5 6 7; do
  row tessellate "$level" --displacement tessellate --displacement-level "$level"
done
cat "$csv"
