#!/usr/bin/env bash
# Object motion blur (issue 24): cost and noise of the moving_spheres scene.
#   results/accuracy/motion_blur.sh BUILD [MAIN_SKETCHTRACE]
# 1. speed: moving_spheres vs the same scene with every velocity/spin removed ("still"; its
#    own specialised kernel, and --general-kernel, which is the moving scene's kernel less the
#    motion part), interleaved, REPEATS times each, 320x200, 16 spp, 1 thread.
# 2. (with MAIN_SKETCHTRACE, a build of the commit this branch started from) the cost of the
#    ray's time field on still scenes: two_spheres and spheres, main vs this build, interleaved
#    in ABBA order (a fixed order read as a 10 % cost on the loaded machine; ABBA showed 1 %).
# 3. error = noise vs spp: RMSE of 4..256 spp against a 2048-spp reference of another seed,
#    moving and still, 160x100, 2 threads.
# Writes raw_motion/*.log and motion_speed.csv / motion_static.csv / motion_noise.csv here.
set -euo pipefail
build=$1
main_bin=${2:-}
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
sketch=$build/miniapps/sketchtrace/sketchtrace
raw=$here/raw_motion
repeats=${REPEATS:-5}
mkdir -p "$raw"
export OMP_PROC_BIND=false

# The still variant: the scene without its motion keys, next to it here (mesh paths adjusted).
still=$raw/still.toml
inputs_from_raw=$(realpath --relative-to="$raw" "$repo/inputs")
sed -e "s#\"\.\./#\"$inputs_from_raw/#" -e '/^velocity/d' -e '/^spin_/d' \
  "$repo/inputs/moving_spheres/moving_spheres.toml" > "$still"
moving=$repo/inputs/moving_spheres/moving_spheres.toml

rate() { sed -n 's/.*render: \([0-9.]*\) s .*, \([0-9]*\) rays, \([0-9.]*\) Mrays\/s.*/\1,\2,\3/p' "$1"; }

echo "variant,repeat,render_s,rays,mrays_per_s" > "$here/motion_speed.csv"
# The order rotates from one repeat to the next, so a load change does not favour one variant.
orders=("still still_general moving" "moving still still_general" "still_general moving still")
for r in $(seq 1 "$repeats"); do
  for v in ${orders[$((r % 3))]}; do
    case $v in
      still) args=("$still") ;;
      still_general) args=("$still" --general-kernel) ;;
      moving) args=("$moving") ;;
    esac
    OMP_NUM_THREADS=1 "$sketch" "${args[@]}" --width 320 --height 200 --spp 16 > "$raw/speed_${v}_$r.log" 2>&1
    echo "$v,$r,$(rate "$raw/speed_${v}_$r.log")" >> "$here/motion_speed.csv"
  done
done

if [[ -n $main_bin ]]; then
  echo "scene,binary,repeat,render_s,rays,mrays_per_s,verification" > "$here/motion_static.csv"
  for r in $(seq 1 "$repeats"); do
    for scene in two_spheres spheres; do
      pair="main branch"
      ((r % 2)) || pair="branch main"  # ABBA: alternate which binary runs first
      for b in $pair; do
        bin=$sketch
        [[ $b == main ]] && bin=$main_bin
        log=$raw/static_${scene}_${b}_$r.log
        OMP_NUM_THREADS=1 "$bin" "$repo/inputs/$scene/$scene.toml" --width 320 --height 200 --spp 4 > "$log" 2>&1
        echo "$scene,$b,$r,$(rate "$log"),$(tail -n 1 "$log" | sed -n 's/.*verification \([0-9a-f]*\)$/\1/p')" >> "$here/motion_static.csv"
      done
    done
  done
fi

echo "variant,spp,rmse,rel_mse,render_s" > "$here/motion_noise.csv"
for v in moving still; do
  scene=$moving
  [[ $v == still ]] && scene=$still
  OMP_NUM_THREADS=2 "$sketch" "$scene" --width 160 --height 100 --spp 2048 --seed 2 \
    -o "$raw/ref_$v.exr" > "$raw/ref_$v.log" 2>&1
  for spp in 4 16 64 256; do
    log=$raw/noise_${v}_$spp.log
    OMP_NUM_THREADS=2 "$sketch" "$scene" --width 160 --height 100 --spp "$spp" \
      --reference "$raw/ref_$v.exr" > "$log" 2>&1
    m=$(sed -n 's/.*RMSE \([0-9.e-]*\), relative MSE \([0-9.e-]*\),.*/\1,\2/p' "$log")
    echo "$v,$spp,$m,$(rate "$log" | cut -d, -f1)" >> "$here/motion_noise.csv"
  done
done
cat "$here/motion_speed.csv" "$here/motion_noise.csv"
[[ -z $main_bin ]] || cat "$here/motion_static.csv"
