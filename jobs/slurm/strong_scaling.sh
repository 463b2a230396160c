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
exec "$(dirname "${BASH_SOURCE[0]}")/scaling_series.sh" strong
