#!/usr/bin/env bash
# Per-rank completion of every sketchtrace load-balancing strategy at a fixed
# rank count (the hand-drawn paper's comparison), then the plot.
# Usage: jobs/local/rank_completion.sh [OUTDIR]
# Environment (defaults in brackets):
#   RTMINI_RANKS       ranks [4]
#   RTMINI_THREADS     OpenMP threads per rank [1]
#   RTMINI_STRATEGIES  --balance values ["static metric chunks bargain queue steal"]
#   RTMINI_INPUT       scene [inputs/two_spheres/two_spheres.toml]
#   RTMINI_OUTDIR      outputs, overridden by OUTDIR [$PWD/rtmini-ranks]
#   RTMINI_BUILD RTMINI_BIN and the sketchtrace knobs: see jobs/lib/rtmini_job.sh
# Writes OUTDIR/<strategy>.{png,json,h5} and OUTDIR/rank_completion.png.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=SCRIPTDIR/../lib/rtmini_job.sh
. "$here/../lib/rtmini_job.sh"
RTMINI_OUTDIR=${1:-${RTMINI_OUTDIR:-$PWD/rtmini-ranks}}
RTMINI_APP=sketchtrace
rtmini_init "$(cd "$here/../.." && pwd)"
RTMINI_INPUT=${RTMINI_INPUT:-$RTMINI_ROOT/inputs/two_spheres/two_spheres.toml}
exe=$(rtmini_binary sketchtrace)
ranks=${RTMINI_RANKS:-4}
rtmini_mpirun_launcher "$ranks" "${RTMINI_THREADS:-1}"

timings=()
for strategy in ${RTMINI_STRATEGIES:-static metric chunks bargain queue steal}; do
  RTMINI_TAG=$strategy RTMINI_BALANCE=$strategy
  rtmini_app_args
  rtmini_banner "${RTMINI_LAUNCH[@]}" "$exe" "${RTMINI_ARGS[@]}"
  "${RTMINI_LAUNCH[@]}" "$exe" "${RTMINI_ARGS[@]}"
  timings+=("$RTMINI_OUTDIR/$strategy.h5")
done
rtmini_python_tool rank_completion -o "$RTMINI_OUTDIR/rank_completion.png" "${timings[@]}"
