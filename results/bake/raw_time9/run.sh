#!/bin/bash
# Bake time of two binaries at RANKS x 1 thread (default 2), alternated REPEATS times (default 3):
# the check that a change added no per-rank overhead, on a machine whose load drifts (the
# alternation lands the drift on both). bunny_room N=300 K=4 (.bsb); each run's summary and the
# load before it are kept; table.py OUT prints the bake times, their median and spread.
# Usage (repository root, build/ built): results/bake/raw_time9/run.sh OUT BAKE_MAIN BAKE_NEW [REPEATS]
set -eu
out=$1 main=$2 new=$3 reps=${4:-3} np=${RANKS:-2}
src=$(cd "$(dirname "$0")/../../.." && pwd)
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false OMP_NUM_THREADS=1
{
  echo "commit $(git -C "$src" rev-parse --short=12 HEAD)"
  echo "date $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "machine $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
  echo "main: $main; new: $new; $np ranks x 1 thread"
} >"$out/provenance.txt"
[ -f "$out/bunny_room.bs" ] || "$src/build/inputs/rtmini-gen-inputs" bunny_room \
  --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_room.bs"
for i in $(seq 1 "$reps"); do
  for which in main new; do
    bin=$main
    [ "$which" = new ] && bin=$new
    name=${which}_$i
    echo "$name load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/provenance.txt"
    mpirun -n "$np" --bind-to none "$bin" "$out/bunny_room.bs" -o "$out/$name.bsb" \
      --viewpoints 300 --iterations 4 --summary "$out/$name.json" >"$out/$name.log" 2>&1
    md5sum "$out/$name.bsb" | cut -d' ' -f1 >"$out/$name.md5"
    rm -f "$out/$name.bsb"
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/provenance.txt"
