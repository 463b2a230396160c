#!/usr/bin/env bash
# Measures the host SAH build against Embree's (issue 22, build row) for results/bvh/README.md
# "SAH build time": BEFORE (a rtmini-bvh-bench built from main) and AFTER (this tree's
# build/bench/rtmini-bvh-bench) run alternately, five runs each, so both see the same machine
# load. Each run times five rtmini SAH builds, each followed by Embree's build of the same
# triangles, and prints the paired ratios (wall and CPU time). Then the tree and the answers on
# every bundled mesh and workload (SAH cost, nodes/tests per ray, verification hashes).
# Writes raw_sahbuild/*.txt next to this script, or into $RTMINI_SAHBUILD_OUT.
# Parts: builds (a tiny traced AO workload, for benches without --build-only), passive (the same
# with OMP_WAIT_POLICY=passive), paired and settled (--build-only at 2 and 1 threads; settled adds
# --settle-ms 50, so each build is charged with its own idle workers' spin-waiting and none of
# earlier work's: both benches need that option), fingerprints (every bundled mesh, the bunny with
# spatial splits and the pre-split sliver fan: the tree's bytes must not change), meshes.
# Usage: results/bvh/sahbuild_measure.sh builds|passive|paired|settled|fingerprints|meshes BEFORE_BENCH [AFTER_BENCH]
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
part=$1
before=$2
after=${3:-$root/build/bench/rtmini-bvh-bench}
out=${RTMINI_SAHBUILD_OUT:-$root/results/bvh/raw_sahbuild}
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
# Paired build timings only (--build-only), back to back or settled.
for mode in paired settled; do
  [ "$part" = $mode ] || continue
  settle=()
  [ $mode = settled ] && settle=(--settle-ms 50)
  for threads in 2 1; do
    for mesh in dragon stanford-bunny; do
      file=build_${mesh}_t${threads}_$mode.txt
      : >"$out/$file"
      for rep in 1 2 3 4 5; do
        for b in "$before" "$after"; do
          run "$file" "$b" "$root/inputs/meshes/$mesh.obj" --build-only --threads "$threads" \
            --peer embree --repeats 5 "${settle[@]}"
        done
      done
    done
  done
done
# The tree's bytes (fingerprint), SAH cost and wide-tree size from both benches.
if [ "$part" = fingerprints ]; then
  file=$out/fingerprints.txt
  : >"$file"
  fan=$(mktemp -d)/fan100k.bs
  "$root/build/inputs/rtmini-gen-inputs" sliver_fan -o "$fan" >/dev/null
  for b in "$before" "$after"; do
    for mesh in teapot cow spot CornellBox-Original stanford-bunny dragon; do
      echo "$mesh $(basename "$b") $("$b" "$root/inputs/meshes/$mesh.obj" --build-only --repeats 1 2>&1 |
        grep -o 'SAH cost [0-9.]*\|wide tree: [0-9]* nodes, [0-9]* leaves\|tree fingerprint [0-9a-f]*' | tr '\n' ' ')" >>"$file"
    done
    echo "stanford-bunny spatial-on $(basename "$b") $("$b" "$root/inputs/meshes/stanford-bunny.obj" \
      --build-only --repeats 1 --spatial-splits on 2>&1 | grep -o 'SAH cost [0-9.]*\|tree fingerprint [0-9a-f]*' | tr '\n' ' ')" >>"$file"
    echo "sliver_fan $(basename "$b") $("$b" "$fan" --build-only --repeats 1 2>&1 |
      grep -o 'SAH cost [0-9.]*\|[0-9]* leaf triangles\|tree fingerprint [0-9a-f]*' | tr '\n' ' ')" >>"$file"
  done
  rm -f "$fan"
fi
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
