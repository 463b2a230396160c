#!/usr/bin/env bash
# README command (1): set up, build, then run the main job on a bundled scene:
# both apps, OpenMP backend, 2 MPI ranks, every output into OUTDIR.
# Usage: jobs/local/demo.sh OUTDIR
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
out=${1:?usage: jobs/local/demo.sh OUTDIR}
"$root/jobs/local/build.sh"
mkdir -p "$out"
out=$(cd "$out" && pwd)
bin=${RTMINI_BUILD_DIR:-$root/build}/miniapps
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} OMP_PROC_BIND=false
mpirun=(mpirun -np 2 --oversubscribe)

echo "== bake: Cornell box, 100 viewpoints, 4 iterations, 2 ranks" >&2
"${mpirun[@]}" "$bin/bake/bake" "$root/inputs/cornell/cornell_box.bs" -o "$out/cornell_baked.bs" \
  --viewpoints 100 --iterations 4 --summary "$out/bake_summary.json" --timings "$out/bake_timings.h5"

echo "== sketchtrace: two spheres, 2 ranks" >&2
"${mpirun[@]}" "$bin/sketchtrace/sketchtrace" "$root/inputs/two_spheres/two_spheres.toml" \
  -o "$out/two_spheres.png" --width 480 --height 360 --spp 16 \
  --summary "$out/sketch_summary.json" --timings "$out/sketch_timings.h5"

echo "== outputs in $out:" >&2
ls -l "$out" >&2
