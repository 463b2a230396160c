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
exec "$(dirname "${BASH_SOURCE[0]}")/scaling_series.sh" weak
