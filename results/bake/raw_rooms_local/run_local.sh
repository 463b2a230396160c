#!/bin/bash
# Local (2-core VM) checks of branch bakeweak: the closed-rooms weak-scaling scene at 1-4 ranks
# and the changed-only exchange (RTMINI_BAKE_CHANGED_EXCHANGE=1) against the full one, same binary.
# (first_e58c8d2/ and second/ ran it when changed-only was the default and
# RTMINI_BAKE_FULL_EXCHANGE=1 chose the full exchange: the line below then set that variable.)
# Usage (repository root, build/ built): results/bake/raw_rooms_local/run_local.sh OUT_DIR [all|bunny]
set -eu
out=$1
what=${2:-all}
src=$(cd "$(dirname "$0")/../../.." && pwd)
bake=${BAKE:-$src/build/miniapps/bake/bake}
gen=$src/build/inputs/rtmini-gen-inputs
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false OMP_NUM_THREADS=1
{
  echo "commit $(git -C "$src" rev-parse --short=12 HEAD) (+ working tree: $(git -C "$src" status --short miniapps | wc -l) files changed)"
  echo "date $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "machine $(nproc --all) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2), shared with other helpers"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} >"$out/provenance.txt"
run() {  # NAME NP EXCHANGE(changed|full) ARGS...
  local name=$1 np=$2 ex=$3
  shift 3
  echo "== $name" >&2
  RTMINI_BAKE_CHANGED_EXCHANGE=$([ "$ex" = changed ] && echo 1 || echo 0) \
    /usr/bin/time -f "wall %e s" -o "$out/$name.time" \
    mpirun -n "$np" --oversubscribe --bind-to none "$bake" "$@" \
    --summary "$out/$name.json" --timings "$out/$name.h5" >"$out/$name.log" 2>&1
  echo "load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/$name.time"
}
for np in 1 2 3 4; do
  [ "$what" = all ] || break
  python3 "$src/results/bake/make_rooms_scene.py" "$np" "$out/rooms_$np.bs"
  for ex in changed full; do
    [ "$np" -gt 1 ] || [ "$ex" = changed ] || continue
    run "rooms_${np}_$ex" "$np" "$ex" "$out/rooms_$np.bs" -o "$out/o.bsb" --viewpoints 200 --iterations 3
  done
  rm -f "$out/rooms_$np.bs"
done
"$gen" bunny_room --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_room.bs" >/dev/null
for i in 1 2 3; do
  for ex in changed full; do
    run "bunny_2_${ex}_$i" 2 "$ex" "$out/bunny_room.bs" -o "$out/o.bsb" --viewpoints 300 --iterations 4
  done
done
for np in 3 4; do
  for ex in changed full; do
    run "bunny_${np}_$ex" "$np" "$ex" "$out/bunny_room.bs" -o "$out/o.bsb" --viewpoints 300 --iterations 4
  done
done
rm -f "$out/o.bsb" "$out/bunny_room.bs"
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/provenance.txt"
