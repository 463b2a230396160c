#!/usr/bin/env bash
# The 800-sliver fan (the unit test's) against the split budget, pre-splitting (spatial splits
# off) and spatial splits on, overview camera. Writes raw_sbvh/fan800_budgets.txt.
# Usage: results/bvh/sbvh_fan_budgets.sh [BENCH]
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bench=${1:-$root/build/bench/rtmini-bvh-bench}
out=$root/results/bvh/raw_sbvh/fan800_budgets.txt
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMP_PROC_BIND=false OMP_NUM_THREADS=1
"$root/build/inputs/rtmini-gen-inputs" sliver_fan --count 800 -o "$tmp/fan800.bs" >/dev/null
{ date -u; uptime; git -C "$root" rev-parse --short HEAD; } >"$out"
for budget in 0 1 3 10 30 100; do
  for sp in off on; do
    echo "### budget $budget spatial $sp" >>"$out"
    nice "$bench" "$tmp/fan800.bs" --workload primary --width 128 --height 128 --camera overview \
      --repeats 1 --spatial-splits "$sp" --split-budget "$budget" 2>&1 |
      grep -E "build:|leaf triangles|per ray|verification" >>"$out"
  done
done
