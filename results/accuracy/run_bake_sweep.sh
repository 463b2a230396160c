#!/bin/bash
# Speed/accuracy sweep of bake (issue 7): the bake knobs one at a time around a base setting on
# the Cornell boxes, each point's map against a traced reference (analysis/rtmini_analysis/
# sweep.py), then the RMSE-vs-time plots with their Pareto frontiers.
# Writes sweep_bake_SCENE.csv, bake_accuracy_rmse.png, bake_accuracy_gather.png and
# bake_pareto.txt into OUT (default: this folder).
# Usage: results/accuracy/run_bake_sweep.sh BUILD_DIR DOUBLE_BUILD_DIR [OUT_DIR]
set -euo pipefail
usage="usage: run_bake_sweep.sh BUILD_DIR DOUBLE_BUILD_DIR [OUT_DIR]"
build=$(cd "${1:?$usage}" && pwd)
double=$(cd "${2:?$usage}" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${3:-$here}
mkdir -p "$out"
out=$(cd "$out" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OMP_PROC_BIND=false
python=${PYTHON:-/usr/bin/python3}
export PYTHONPATH=$root/analysis MPLBACKEND=Agg

csvs=()
for scene in cornell_big/cornell_big_raw cornell/cornell_box; do
  name=$(basename "$scene")
  echo "== $name: load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%FT%TZ)"
  "$python" -m rtmini_analysis.sweep --bake "$build/miniapps/bake/bake" \
    --bake-double "$double/miniapps/bake/bake" --scene "$root/inputs/$scene.bs" \
    --repeat 3 --workdir "$work/$name" -o "$out/sweep_bake_$name.csv"
  csvs+=("$out/sweep_bake_$name.csv")
done
echo "== done: load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%FT%TZ)"
{
  "$python" -m rtmini_analysis.accuracy "${csvs[@]}" --error-name rmse -o "$out/bake_accuracy_rmse.png"
  "$python" -m rtmini_analysis.accuracy "${csvs[@]}" --error-name rmse_vs_gather256 \
    -o "$out/bake_accuracy_gather.png"
} | tee "$out/bake_pareto.txt"
