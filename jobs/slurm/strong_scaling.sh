#!/usr/bin/env bash
# Strong scaling with Slurm: one cpu_node.sbatch job per rank count, same
# problem each time; optionally a dependent job that draws the scaling plot.
# Job arrays cannot vary --ntasks, so this submits one job per point.
# Usage (from the repository root): jobs/slurm/strong_scaling.sh
# Environment (defaults in brackets), plus everything cpu_node.sbatch reads:
#   RTMINI_ROOT           repository root [this script's ../..]
#   RTMINI_RANKS          rank counts ["1 2 4 8 16"]
#   RTMINI_THREADS        OpenMP threads per rank [1]
#   RTMINI_RANKS_PER_NODE ranks per node, sets --nodes [16]
#   RTMINI_OUTDIR         outputs [$PWD/rtmini-strong]; tags are strong-<ranks>
#   RTMINI_SEQUENTIAL     1 = each job waits for the previous one (clean timings
#                         on shared nodes) [0]
#   RTMINI_ANALYZE        1 = submit a dependent job running rtmini_analysis.scaling [0]
#   RTMINI_SBATCH_ARGS    extra sbatch options, e.g. "-A proj -p batch" []
#   RTMINI_PYTHON         Python with numpy/matplotlib/h5py for the plot job [python3]
#   RTMINI_ENV_HOOK       bash file of `module load` lines, sourced by every job first []
# Prints the submitted job ids, one per line.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=${RTMINI_ROOT:-$(cd "$here/../.." && pwd)}
outdir=${RTMINI_OUTDIR:-$PWD/rtmini-strong}
threads=${RTMINI_THREADS:-1}
per_node=${RTMINI_RANKS_PER_NODE:-16}
read -r -a extra <<<"${RTMINI_SBATCH_ARGS:-}"
mkdir -p "$outdir"

ids=()
dep=()
for r in ${RTMINI_RANKS:-1 2 4 8 16}; do
  nodes=$(((r + per_node - 1) / per_node))
  id=$(sbatch --parsable "${dep[@]}" "${extra[@]}" --job-name="rtmini-strong-$r" \
    --nodes="$nodes" --ntasks="$r" --ntasks-per-node="$(((r + nodes - 1) / nodes))" --cpus-per-task="$threads" \
    --output="$outdir/strong-$r-%j.out" \
    --export="ALL,RTMINI_ROOT=$root,RTMINI_OUTDIR=$outdir,RTMINI_TAG=strong-$r" \
    "$root/jobs/slurm/cpu_node.sbatch")
  ids+=("$id")
  echo "$id"
  if [ "${RTMINI_SEQUENTIAL:-0}" = 1 ]; then
    dep=(--dependency="afterany:$id")
  fi
done

if [ "${RTMINI_ANALYZE:-0}" = 1 ]; then
  hook=""
  if [ -n "${RTMINI_ENV_HOOK:-}" ]; then hook=". '$RTMINI_ENV_HOOK' && "; fi
  after=$(IFS=:; echo "${ids[*]}")
  sbatch --parsable "${extra[@]}" --job-name=rtmini-strong-plot --ntasks=1 \
    --dependency="afterany:$after" --output="$outdir/plot-%j.out" \
    --wrap="${hook}cd '$root/analysis' && PYTHONPATH=. '${RTMINI_PYTHON:-python3}' -m rtmini_analysis.scaling --mode strong -o '$outdir/strong_scaling.png' '$outdir'/strong-*.json"
fi
