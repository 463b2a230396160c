#!/bin/bash
# Re-runs the bake measurements of results/bake/README.md. Usage:
#   results/bake/run_benchmarks.sh BUILD_DIR OUT_DIR [cornell|scaling|bunny|all]
# Logs (stdout/stderr of each run, /usr/bin/time output, timings .h5, summaries) go to OUT_DIR.
set -eu
build=$(cd "$1" && pwd)
out=$2
what=${3:-all}
src=$(cd "$(dirname "$0")/../.." && pwd)
bake=$build/miniapps/bake/bake
gen=$build/inputs/rtmini-gen-inputs
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false
big=$src/inputs/cornell_big/cornell_big_raw.bs
{
  echo "commit $(git -C "$src" rev-parse --short=12 HEAD) (working tree may differ: $(git -C "$src" status --porcelain | wc -l) changed paths)"
  echo "date $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "machine $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} >"$out/provenance.txt"

if [ "$what" = cornell ] || [ "$what" = all ]; then
  for rep in 1 2 3; do
    OMP_NUM_THREADS=2 /usr/bin/time -f "wall %e s, user %U s, maxrss %M KiB" \
      "$bake" "$big" -o "$out/cornell_big_n100_k4.bs" --viewpoints 100 --iterations 4 \
      --summary "$out/cornell_big_n100_k4_rep$rep.json" >"$out/cornell_big_n100_k4_rep$rep.log" 2>&1
  done
fi
if [ "$what" = scaling ] || [ "$what" = all ]; then
  for balance in cost static; do
    for np in 1 2 4; do
      OMP_NUM_THREADS=1 /usr/bin/time -f "wall %e s" mpirun -n $np --oversubscribe "$bake" "$big" \
        -o "$out/scaling.bs" --viewpoints 1000 --iterations 4 --balance $balance \
        --timings "$out/scaling_${balance}_np$np.h5" --summary "$out/scaling_${balance}_np$np.json" \
        >"$out/scaling_${balance}_np$np.log" 2>&1
    done
  done
fi
if [ "$what" = bunny ] || [ "$what" = all ]; then
  "$gen" bunny --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_bake.bs"
  OMP_NUM_THREADS=2 /usr/bin/time -f "wall %e s, user %U s, maxrss %M KiB" "$bake" \
    "$out/bunny_bake.bs" -o "$out/bunny_n1000_k4.bs" --viewpoints 1000 --iterations 4 --progress \
    --timings "$out/bunny_n1000_k4.h5" --summary "$out/bunny_n1000_k4.json" \
    >"$out/bunny_n1000_k4.log" 2>&1
  rm -f "$out/bunny_n1000_k4.bs"  # 2 GiB
fi
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/provenance.txt"
