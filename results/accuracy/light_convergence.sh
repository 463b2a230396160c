#!/bin/bash
# Issue 24, "light that converges": how fast sketchtrace's estimate approaches a high-sample
# reference, before and after next-event estimation through glossy lobes with MIS, full
# shadow sampling behind mirrors and clear glass, solid-angle quad sampling and joint
# pixel/light stratification. Two binaries render the bundled scenes
# inputs/light_converge/{reflected_shadow,glass}.toml at 1..64 samples per pixel; each run's
# RMSE against the reference (the AFTER binary at REFSPP pixel samples, another seed) and its
# render time go to light_convergence.csv, three seeds per point. A second reference from the
# BEFORE binary, and a third from AFTER, check that both estimate the same image (bias) up to
# the references' noise. A stratification table renders inputs/light_converge/penumbra.toml
# (direct light, no edges in view) with spp x shadow samples = 16 in every split, three seeds
# each. Raw logs and JSON summaries: OUT/raw_light/. light_convergence_report.py turns the
# CSV into light_convergence.md and .png.
# Usage: results/accuracy/light_convergence.sh AFTER_SKETCHTRACE BEFORE_SKETCHTRACE [OUT_DIR]
# Environment: REFSPP (default 1024), OMP_NUM_THREADS (default 2).
set -euo pipefail
after=$(realpath "${1:?usage: light_convergence.sh AFTER BEFORE [OUT_DIR]}")
before=$(realpath "${2:?usage: light_convergence.sh AFTER BEFORE [OUT_DIR]}")
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${3:-$here}
mkdir -p "$out/raw_light"
out=$(cd "$out" && pwd)
raw=$out/raw_light
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OMP_PROC_BIND=false
refspp=${REFSPP:-1024}
csv=$out/light_convergence.csv
timing_only=${TIMING_ONLY:-0}  # 1: only the timing repeats, appended to an existing CSV
[ "$timing_only" = 1 ] || echo "scene,binary,spp,shadow_samples,bounces,seed,rmse,render_s,rays" >"$csv"

# run ID BINARY SCENE ARGS...: render into ID.exr, log and summary into raw/.
run() {
  local id=$1 bin=$2 scene=$3
  shift 3
  echo "$(basename "$bin") inputs/light_converge/$scene.toml $*" >"$raw/$id.log"
  "$bin" "$root/inputs/light_converge/$scene.toml" -o "$work/$id.exr" "$@" \
    --summary "$raw/$id.json" >>"$raw/$id.log" 2>&1
}

# row ID SCENE BINARY SPP SHADOW BOUNCES SEED: a CSV row from ID.json.
row() {
  /usr/bin/python3 - "$raw/$1.json" "${@:2}" >>"$csv" <<'PY'
import json, sys
t = json.load(open(sys.argv[1]))
secs = t["phases"].get("render", t["phases"]["total"])
rays = t["scene"]["rays"]
rmse = f'{t["errors"]["rmse"]:.6f}' if "errors" in t else ""
print(",".join(sys.argv[2:]) + f",{rmse},{secs:.3f},{rays}")
PY
}

for scene in reflected_shadow glass; do
  [ "$timing_only" = 1 ] && break
  run "${scene}_ref" "$after" "$scene" --spp "$refspp" --seed 9001
  run "${scene}_ref_before" "$before" "$scene" --spp "$refspp" --seed 9002 \
    --reference "$work/${scene}_ref.exr"
  row "${scene}_ref_before" "$scene" before_reference "$refspp" 4 default 9002
  run "${scene}_ref_after2" "$after" "$scene" --spp "$refspp" --seed 9003 \
    --reference "$work/${scene}_ref.exr"
  row "${scene}_ref_after2" "$scene" after_reference "$refspp" 4 default 9003
  for spp in 1 2 4 8 16 32 64; do
    for seed in 5 6 7; do
      for bin in before after; do
        b=$before
        [ $bin = after ] && b=$after
        run "${scene}_${bin}_${spp}_$seed" "$b" "$scene" --spp "$spp" --seed "$seed" \
          --reference "$work/${scene}_ref.exr"
        row "${scene}_${bin}_${spp}_$seed" "$scene" "$bin" "$spp" 4 default "$seed"
      done
    done
  done
done

# Joint stratification: direct light only, 16 shadow rays per pixel split every way.
[ "$timing_only" = 1 ] || run strat_ref "$after" penumbra --spp 256 --shadow-samples 64 --seed 9004
for split in 16x1 8x2 4x4 2x8 1x16; do
  [ "$timing_only" = 1 ] && break
  spp=${split%x*} sh=${split#*x}
  for seed in 1 2 3; do
    for bin in before after; do
      b=$before
      [ $bin = after ] && b=$after
      run "strat_${bin}_${split}_$seed" "$b" penumbra --spp "$spp" --shadow-samples "$sh" \
        --seed "$seed" --reference "$work/strat_ref.exr"
      row "strat_${bin}_${split}_$seed" penumbra "$bin" "$spp" "$sh" 0 "$seed"
    done
  done
done
# Cost: 5 interleaved repeats of each binary at 32 spp (the report takes the minimum, the run
# least disturbed by other work on a shared machine, and shows the spread).
for scene in reflected_shadow glass; do
  for rep in 1 2 3 4 5; do
    for bin in before after; do
      b=$before
      [ $bin = after ] && b=$after
      run "time_${scene}_${bin}_$rep" "$b" "$scene" --spp 32 --seed 5
      row "time_${scene}_${bin}_$rep" "timing_$scene" "$bin" 32 4 default "$rep"
    done
  done
done
echo "wrote $csv"
