#!/usr/bin/env bash
# Measures the spatial splits of the SAH build (results/bvh/slivers.md, "Spatial splits"): every
# bundled mesh built with --spatial-splits off and on, one process per run, off and on
# alternating and the meshes interleaved so both see the same machine load (5 rounds, primary
# rays); one AO run each for the hashes; then the sliver fan at several split budgets.
# Writes raw_sbvh/*.txt next to this script. Usage: results/bvh/sbvh_measure.sh [BENCH]
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bench=${1:-$root/build/bench/rtmini-bvh-bench}
gen=$root/build/inputs/rtmini-gen-inputs
out=$root/results/bvh/raw_sbvh
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
export OMP_PROC_BIND=false
run() {  # file args...
  local file=$1
  shift
  { echo "### $bench $*"; date -u; uptime; nice "$bench" "$@" 2>&1 | grep -v '^Kokkos::OpenMP\|OMP_PROC_BIND\|OpenMP 3.1\|For unit testing'; } >>"$out/$file.txt"
}
meshes="teapot.obj cow.obj spot.obj CornellBox-Original.obj stanford-bunny.obj dragon.obj"
: >"$out/meshes_primary.txt"
for round in 1 2 3 4 5; do
  for mesh in $meshes; do
    for sp in off on; do
      run meshes_primary "$root/inputs/meshes/$mesh" --workload primary --width 256 --height 256 \
        --repeats 1 --spatial-splits "$sp"
    done
  done
done
: >"$out/meshes_ao.txt"
for mesh in $meshes; do
  for sp in off on; do
    run meshes_ao "$root/inputs/meshes/$mesh" --workload ao --samples-per-face 1 --rays 4 \
      --repeats 1 --spatial-splits "$sp"
  done
done
"$gen" sliver_fan -o "$tmp/fan100k.bs" >/dev/null
: >"$out/fan.txt"
for args in "off 0" "off 1" "on 1" "on 3"; do
  set -- $args
  run fan "$tmp/fan100k.bs" --workload primary --width 128 --height 128 --camera overview \
    --repeats 1 --spatial-splits "$1" --split-budget "$2"
done
