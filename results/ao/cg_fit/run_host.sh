#!/usr/bin/env bash
# Cholesky vs device CG (here: the OpenMP backend) for the AO least-squares fit, interleaved,
# REPS repetitions per (scene, threads, fit). The fit does not depend on the ray count, so the
# bakes trace 4 rays per sample point to keep the runs short.
# Usage: results/ao/cg_fit/run_host.sh BUILD_DIR OUT_DIR [REPS]
set -euo pipefail
build=$1 out=$2 reps=${3:-5}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)
mkdir -p "$out"
export OMP_PROC_BIND=false
for rep in $(seq 1 "$reps"); do
  for threads in 1 2; do
    for scene in spot_instances dragon_x4; do
      extra=()
      [[ $scene == dragon_x4 ]] && extra=(-s 1250000)
      for fit in cholesky cg; do
        tag=${scene}_t${threads}_${fit}_rep${rep}
        OMP_NUM_THREADS=$threads nice "$build/miniapps/bake/ao/rtmini-ao" "$root/inputs/ao/$scene.toml" \
          "${extra[@]}" -r 4 --fit "$fit" --summary "$out/$tag.json" > "$out/$tag.log" 2>&1
      done
    done
  done
done
