#!/usr/bin/env bash
# Weak scaling with Slurm: one cpu_node.sbatch job per rank count, with the
# work per rank held constant by multiplying one knob by the rank count:
# samples per pixel for sketchtrace (same image, r times the samples),
# viewpoints per vertex for bake. Optionally a dependent plotting job.
# Usage (from the repository root): jobs/slurm/weak_scaling.sh
# Environment (defaults in brackets), plus everything cpu_node.sbatch reads:
#   RTMINI_ROOT           repository root [this script's ../..]
#   RTMINI_APP            sketchtrace | bake [sketchtrace]
#   RTMINI_RANKS          rank counts ["1 2 4 8 16"]
#   RTMINI_WEAK_BASE      knob value at one rank: --spp or --viewpoints [16]
#   RTMINI_THREADS        OpenMP threads per rank [1]
#   RTMINI_RANKS_PER_NODE ranks per node, sets --nodes [16]
#   RTMINI_OUTDIR         outputs [$PWD/rtmini-weak]; tags are weak-<ranks>
#   RTMINI_SEQUENTIAL     1 = each job waits for the previous one [0]
#   RTMINI_ANALYZE        1 = submit a dependent job running rtmini_analysis.scaling [0]
#   RTMINI_SBATCH_ARGS    extra sbatch options, e.g. "-A proj -p batch" []
#   RTMINI_PYTHON         Python with numpy/matplotlib/h5py for the plot job [python3]
#   RTMINI_ENV_HOOK       bash file of `module load` lines, sourced by every job first []
# Prints the submitted job ids, one per line.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=${RTMINI_ROOT:-$(cd "$here/../.." && pwd)}
outdir=${RTMINI_OUTDIR:-$PWD/rtmini-weak}
threads=${RTMINI_THREADS:-1}
per_node=${RTMINI_RANKS_PER_NODE:-16}
base=${RTMINI_WEAK_BASE:-16}
if [ "${RTMINI_APP:-sketchtrace}" = bake ]; then knob=RTMINI_VIEWPOINTS; else knob=RTMINI_SPP; fi
read -r -a extra <<<"${RTMINI_SBATCH_ARGS:-}"
mkdir -p "$outdir"

ids=()
dep=()
for r in ${RTMINI_RANKS:-1 2 4 8 16}; do
  nodes=$(((r + per_node - 1) / per_node))
  id=$(sbatch --parsable "${dep[@]}" "${extra[@]}" --job-name="rtmini-weak-$r" \
    --nodes="$nodes" --ntasks="$r" --ntasks-per-node="$(((r + nodes - 1) / nodes))" --cpus-per-task="$threads" \
    --output="$outdir/weak-$r-%j.out" \
    --export="ALL,RTMINI_ROOT=$root,RTMINI_OUTDIR=$outdir,RTMINI_TAG=weak-$r,$knob=$((base * r))" \
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
  sbatch --parsable "${extra[@]}" --job-name=rtmini-weak-plot --ntasks=1 \
    --dependency="afterany:$after" --output="$outdir/plot-%j.out" \
    --wrap="${hook}cd '$root/analysis' && PYTHONPATH=. '${RTMINI_PYTHON:-python3}' -m rtmini_analysis.scaling --mode weak -o '$outdir/weak_scaling.png' '$outdir'/weak-*.json"
fi
