#!/bin/bash
# The quick A/B loop of branch sahbuild6's exploration (results/bvh/README.md, "Tried and dropped"):
# alternates the benches given, REPS times, each timing 11 paired SAH builds (rtmini, then Embree)
# on one mesh, and prints each run's rtmini / Embree CPU ms and CPU-time ratio median [min, max].
# Usage (from the repository root): results/bvh/raw_sahbuild6/ab.sh MESH THREADS REPS BENCH...
mesh=$1; t=$2; reps=$3; shift 3
export OMP_PROC_BIND=false
for r in $(seq "$reps"); do for b in "$@"; do
  l=$("$b" "inputs/meshes/$mesh.obj" --build-only --threads "$t" --time-builds sah --peer embree \
    --repeats 11 --settle-ms 20 2>&1 | grep "ms CPU")
  echo "$(basename "$b") $(echo "$l" | sed -E 's/.*wall, ratio median [^;]*; //; s/ ms CPU, ratio median/ /; s/ ms vs/ /')"
done; done
