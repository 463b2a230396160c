#!/bin/bash
# Measures results/accuracy/extremes.md: the stability cases of
# tests/regression/stability/extremes_checks.sh, every comparison reported (KEEP_GOING=1), for
# the binaries of one build, including placements beyond the suite's (the valid range).
# Usage: results/accuracy/extremes_measure.sh BUILD_DIR TAG [AGREE_BUILD_DIR]
#   writes results/accuracy/raw_extremes/TAG/{sketch_cornell,bake_cornell,ao_disk}.log
set -u
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$(cd "$1" && pwd)  # absolute: the cases run in their own folders
tag=$2
agree_build=$(cd "${3:-$build}" && pwd)
out=$root/results/accuracy/raw_extremes/$tag
mkdir -p "$out"
export SKETCH=$build/miniapps/sketchtrace/sketchtrace BAKE=$build/miniapps/bake/bake
export AGREE=$agree_build/tests/regression/stability/rtmini-image-agreement INPUTS=$root/inputs
export KEEP_GOING=1 OMP_NUM_THREADS=2 OMP_PROC_BIND=false
export EXTRA_PLACEMENTS="s1e-10 1e-10 0
s1e10 1e10 0
s1e-12 1e-12 0
s1e12 1e12 0
s1e14 1e14 0
t1e9 1 1e9
t1e10 1 1e10"
checks=$(mktemp)
cp "$root/tests/regression/stability/extremes_checks.sh" "$checks"
for c in sketch_cornell bake_cornell ao_disk; do
  {
    echo "# $(date -u +%FT%TZ) $(git -C "$root" rev-parse --short HEAD) $(hostname) $(nproc) cores (shared)"
    echo "# SKETCH=$SKETCH BAKE=$BAKE"
    bash "$checks" "$c" "/tmp/rtmini_extremes_$tag/$c"
  } >"$out/$c.log" 2>&1
  echo "$c:"
  grep -v '^Mean AO' "$out/$c.log"
done
rm -f "$checks"
