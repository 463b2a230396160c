#!/usr/bin/env bash
# PLOC with and without treelet restructuring on the host: SAH costs and build times, the two
# binaries interleaved, 5 runs each. Usage: run.sh BASE_BENCH NEW_BENCH OUT_DIR
set -euo pipefail
base=$1 new=$2 out=$3
mkdir -p "$out"
for rep in 1 2 3 4 5; do
  for mesh in stanford-bunny dragon; do
    for which in base new; do
      bin=$base; [ "$which" = new ] && bin=$new
      OMP_NUM_THREADS=2 OMP_PROC_BIND=false "$bin" "inputs/meshes/$mesh.obj" \
        --time-builds lbvh,ploc,sah --build-phases --samples-per-face 1 --rays 1 --repeats 1 \
        > "$out/$mesh.$which.$rep.txt" 2>&1
    done
  done
done
