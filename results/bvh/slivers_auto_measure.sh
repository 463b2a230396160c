#!/usr/bin/env bash
# Measures the auto split budget (results/bvh/slivers.md, "The auto split budget"): the 100K
# sliver fan with the overview and the framed camera, and every bundled mesh (tree fingerprint,
# SAH build time, primary-ray hash and rate), BEFORE (the base's default budget of 1) and AFTER
# (auto) alternating so both see the same machine load. Peak RSS from /usr/bin/time -v.
# Writes raw_auto/*.txt next to this script.
# Usage: results/bvh/slivers_auto_measure.sh BEFORE_BENCH AFTER_BENCH [fan|meshes|all]
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
before=$1
after=$2
what=${3:-all}
gen=$root/build/inputs/rtmini-gen-inputs
out=$root/results/bvh/raw_auto
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$out"
export OMP_PROC_BIND=false OMP_NUM_THREADS=2
run() {  # file label bench args...
  local file=$1 label=$2 bench=$3
  shift 3
  {
    echo "### $label: rtmini-bvh-bench $*"
    date -u
    uptime
    /usr/bin/time -v nice "$bench" "$@" 2>&1 |
      grep -v '^Kokkos::OpenMP\|OMP_PROC_BIND\|OpenMP 3.1\|For unit testing' |
      grep -v '^	[A-Z].*: 0$\|Average\|Page size\|Signals\|Socket\|Swaps\|File system\|context switches\|page faults'
  } | sed "s#$tmp/##g; s#$root/##g" >>"$out/$file.txt"
}
if [ "$what" = fan ] || [ "$what" = all ]; then
  "$gen" sliver_fan -o "$tmp/fan.bs" >/dev/null
  : >"$out/fan.txt"
  for cam in overview framed; do
    run fan before "$before" "$tmp/fan.bs" --workload primary --width 128 --height 128 \
      --camera "$cam" --repeats 3 --time-builds sah
    run fan after "$after" "$tmp/fan.bs" --workload primary --width 128 --height 128 \
      --camera "$cam" --repeats 3 --time-builds sah
  done
  for budget in 0 1 31 63; do
    run fan "after, budget $budget" "$after" "$tmp/fan.bs" --workload primary --width 128 \
      --height 128 --camera overview --repeats 1 --time-builds sah --split-budget "$budget"
  done
fi
if [ "$what" = meshes ] || [ "$what" = all ]; then
  meshes="teapot.obj cow.obj spot.obj CornellBox-Original.obj stanford-bunny.obj dragon.obj"
  : >"$out/meshes_build.txt"
  for round in 1 2 3 4 5; do
    for mesh in $meshes; do
      for side in before after; do
        bench=$before
        [ "$side" = after ] && bench=$after
        run meshes_build "$side" "$bench" "$root/inputs/meshes/$mesh" --build-only \
          --time-builds sah --repeats 3
      done
    done
  done
  : >"$out/meshes_primary.txt"
  for round in 1 2 3; do
    for mesh in $meshes; do
      for side in before after; do
        bench=$before
        [ "$side" = after ] && bench=$after
        run meshes_primary "$side" "$bench" "$root/inputs/meshes/$mesh" --workload primary \
          --width 256 --height 256 --repeats 3 --time-builds sah
      done
    done
  done
fi
