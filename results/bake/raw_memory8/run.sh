#!/bin/bash
# Peak RSS per rank of bunny_room N=300 K=4 (.bsb) at 1, 2, 4 and 16 ranks x 1 thread (RANKS
# overrides the list), two bake binaries alternated (main's, then this branch's, per rank count),
# each run's summary kept and its output's md5. Memory only: on a shared 2-core VM the runs of
# more than 2 ranks are oversubscribed and every time is noise.
# MAIN_ARGS / NEW_ARGS: extra bake options of each (e.g. MAIN_ARGS="--max-colors 0": one binary,
# the cap off against on), MPIRUN_ARGS: extra mpirun options of both.
# Usage (repository root): results/bake/raw_memory8/run.sh OUT BAKE_MAIN BAKE_NEW [REPEATS]
set -eu
out=$1 main=$2 new=$3 reps=${4:-1}
src=$(cd "$(dirname "$0")/../../.." && pwd)
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false OMP_NUM_THREADS=1
{
  echo "commit $(git -C "$src" rev-parse --short=12 HEAD)"
  echo "date $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "machine $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
  echo "main: $main ${MAIN_ARGS:-}; new: $new ${NEW_ARGS:-}; mpirun ${MPIRUN_ARGS:-}"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} >"$out/provenance.txt"
[ -f "$out/bunny_room.bs" ] || "$src/build/inputs/rtmini-gen-inputs" bunny_room \
  --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_room.bs"
for i in $(seq 1 "$reps"); do
  for np in ${RANKS:-1 2 4 16}; do
    for which in main new; do
      bin=$main args=${MAIN_ARGS:-}
      [ "$which" = new ] && bin=$new args=${NEW_ARGS:-}
      name=${which}_${np}_$i
      echo "== $name (load $(cut -d' ' -f1 /proc/loadavg))" >&2
      # shellcheck disable=SC2086 # the extra options are word lists
      mpirun -n "$np" --oversubscribe --bind-to none ${MPIRUN_ARGS:-} "$bin" "$out/bunny_room.bs" -o "$out/$name.bsb" \
        --viewpoints 300 --iterations 4 --summary "$out/$name.json" $args >"$out/$name.log" 2>&1
      md5sum "$out/$name.bsb" | cut -d' ' -f1 >"$out/$name.md5"
      rm -f "$out/$name.bsb"
    done
  done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/provenance.txt"
