#!/usr/bin/env bash
# The submission loop shared by strong_scaling.sh and weak_scaling.sh (their headers document
# the environment): one cpu_node.sbatch job per rank count, tagged MODE-<ranks>, and optionally
# a dependent job that draws the MODE scaling plot. For weak scaling the knob that sets the work
# (--spp for sketchtrace, --viewpoints for bake) is RTMINI_WEAK_BASE times the rank count.
# Job arrays cannot vary --ntasks, so this submits one job per point.
# Usage: scaling_series.sh strong|weak. Prints the submitted job ids, one per line.
set -euo pipefail

mode=$1
case "$mode" in strong | weak) ;; *) echo "scaling_series.sh: mode must be strong or weak, got '$mode'" >&2; exit 2 ;; esac
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=${RTMINI_ROOT:-$(cd "$here/../.." && pwd)}
outdir=${RTMINI_OUTDIR:-$PWD/rtmini-$mode}
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
  work=""
  if [ "$mode" = weak ]; then work=",$knob=$((base * r))"; fi
  id=$(sbatch --parsable "${dep[@]}" "${extra[@]}" --job-name="rtmini-$mode-$r" \
    --nodes="$nodes" --ntasks="$r" --ntasks-per-node="$(((r + nodes - 1) / nodes))" --cpus-per-task="$threads" \
    --output="$outdir/$mode-$r-%j.out" \
    --export="ALL,RTMINI_ROOT=$root,RTMINI_OUTDIR=$outdir,RTMINI_TAG=$mode-$r$work" \
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
  sbatch --parsable "${extra[@]}" --job-name="rtmini-$mode-plot" --ntasks=1 \
    --dependency="afterany:$after" --output="$outdir/plot-%j.out" \
    --wrap="${hook}cd '$root/analysis' && PYTHONPATH=. '${RTMINI_PYTHON:-python3}' -m rtmini_analysis.scaling --mode $mode -o '$outdir/${mode}_scaling.png' '$outdir'/$mode-*.json"
fi
