#!/usr/bin/env bash
# Measures the host SAH build against Embree's (issue 22, build row) for results/bvh/README.md
# "SAH build time": BEFORE (a rtmini-bvh-bench built from main) and AFTER (this tree's
# build/bench/rtmini-bvh-bench) run alternately, five runs each, so both see the same machine
# load. Each run times five rtmini SAH builds, each followed by Embree's build of the same
# triangles, and prints the paired ratios (wall and CPU time). Then the tree and the answers on
# every bundled mesh and workload (SAH cost, nodes/tests per ray, verification hashes).
# Writes raw_sahbuild/*.txt next to this script.
# Usage: results/bvh/sahbuild_measure.sh builds|passive|meshes BEFORE_BENCH [AFTER_BENCH]
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
part=$1
before=$2
after=${3:-$root/build/bench/rtmini-bvh-bench}
out=$root/results/bvh/raw_sahbuild
mkdir -p "$out"
export OMP_PROC_BIND=false
run() {  # file bench args...
  local file=$1 bench=$2
  shift 2
  { echo "### $bench $*"; echo "# env: OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-unset}"; uptime
    "$bench" "$@" 2>&1 | grep -v '^Kokkos::OpenMP\|OMP_PROC_BIND\|OpenMP 3.1\|For unit testing'; } >>"$out/$file"
}
# Build times: a tiny AO workload so the trace is short (main's bench has no --build-only).
[ "$part" = builds ] && for threads in 2 1; do
  for mesh in dragon stanford-bunny; do
    file=build_${mesh}_t$threads.txt
    : >"$out/$file"
    for rep in 1 2 3 4 5; do
      for b in "$before" "$after"; do
        run "$file" "$b" "$root/inputs/meshes/$mesh.obj" --threads "$threads" --peer embree \
          --repeats 5 --samples-per-face 1 --rays 4
      done
    done
  done
done
# The same with OpenMP threads that sleep at once when idle (no spin-waiting counted as CPU time).
[ "$part" = passive ] && for mesh in dragon stanford-bunny; do
  file=build_${mesh}_t2_passive.txt
  : >"$out/$file"
  for rep in 1 2 3; do
    for b in "$before" "$after"; do
      OMP_WAIT_POLICY=passive run "$file" "$b" "$root/inputs/meshes/$mesh.obj" --threads 2 \
        --peer embree --repeats 5 --samples-per-face 1 --rays 4
    done
  done
done
# Trees and answers on every bundled mesh and workload.
[ "$part" = meshes ] && : >"$out/meshes.txt" && for mesh in teapot.obj cow.obj spot.obj CornellBox-Original.obj stanford-bunny.obj dragon.obj; do
  for b in "$before" "$after"; do
    run meshes.txt "$b" "$root/inputs/meshes/$mesh" --workload ao --samples-per-face 1 --rays 8 --repeats 3
    for w in primary shadow diffuse; do
      run meshes.txt "$b" "$root/inputs/meshes/$mesh" --workload $w --width 512 --height 512 --repeats 3
    done
  done
done
