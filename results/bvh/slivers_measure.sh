#!/usr/bin/env bash
# Re-measures results/bvh/slivers.md: the sliver fan (issue 18) and every bundled mesh, the SAH
# build before (BEFORE: a rtmini-bvh-bench built from main) and after (AFTER: this tree's
# build/bench/rtmini-bvh-bench), run alternately so both see the same machine load; then the
# build-time comparison with Embree (issue 22). Writes raw/slivers_*.txt next to this script.
# Usage: results/bvh/slivers_measure.sh BEFORE_BENCH [AFTER_BENCH]
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
before=$1
after=${2:-$root/build/bench/rtmini-bvh-bench}
gen=$root/build/inputs/rtmini-gen-inputs
out=$root/results/bvh/raw_slivers
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
export OMP_PROC_BIND=false
"$gen" sliver_fan -o "$tmp/fan100k.bs" >/dev/null
run() {  # label bench args...
  local label=$1 bench=$2
  shift 2
  { echo "### $label: $bench $*"; uptime; nice "$bench" "$@" 2>&1 | grep -v '^Kokkos::OpenMP\|OMP_PROC_BIND\|OpenMP 3.1\|For unit testing'; } >>"$out/slivers_$label.txt"
}
: >"$out/slivers_fan.txt"
for b in "$before" "$after"; do
  run fan "$b" "$tmp/fan100k.bs" --workload primary --width 256 --height 256 --repeats 3
done
: >"$out/slivers_meshes.txt"
for mesh in teapot.obj cow.obj spot.obj CornellBox-Original.obj stanford-bunny.obj dragon.obj; do
  for b in "$before" "$after"; do
    run meshes "$b" "$root/inputs/meshes/$mesh" --workload primary --width 512 --height 512 --repeats 5
    run meshes "$b" "$root/inputs/meshes/$mesh" --workload ao --samples-per-face 1 --rays 8 --repeats 5
  done
done
: >"$out/slivers_embree.txt"
for mesh in stanford-bunny.obj dragon.obj; do
  for b in "$before" "$after"; do
    run embree "$b" "$root/inputs/meshes/$mesh" --peer embree --repeats 5 --samples-per-face 1 --rays 8
  done
done
