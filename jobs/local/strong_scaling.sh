#!/usr/bin/env bash
# Strong scaling on one machine with mpirun: the same run at each rank count,
# then the scaling plot. Usage: jobs/local/strong_scaling.sh [OUTDIR]
# Environment (defaults in brackets):
#   RTMINI_RANKS     rank counts ["1 2 4"]
#   RTMINI_THREADS   OpenMP threads per rank [1]
#   RTMINI_OUTDIR    outputs, overridden by OUTDIR [$PWD/rtmini-strong]
#   RTMINI_BUILD RTMINI_BIN RTMINI_APP RTMINI_INPUT and the app knobs
#   (RTMINI_WIDTH ... RTMINI_EXTRA_ARGS): see jobs/lib/rtmini_job.sh
# Writes OUTDIR/strong-<ranks>.{png|bs,json,h5} and OUTDIR/strong_scaling.png.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=SCRIPTDIR/../lib/rtmini_job.sh
. "$here/../lib/rtmini_job.sh"
RTMINI_OUTDIR=${1:-${RTMINI_OUTDIR:-$PWD/rtmini-strong}}
rtmini_init "$(cd "$here/../.." && pwd)"
exe=$(rtmini_binary "$RTMINI_APP")
threads=${RTMINI_THREADS:-1}

summaries=()
for r in ${RTMINI_RANKS:-1 2 4}; do
  RTMINI_TAG=strong-$r
  rtmini_app_args
  rtmini_mpirun_launcher "$r" "$threads"
  rtmini_banner "${RTMINI_LAUNCH[@]}" "$exe" "${RTMINI_ARGS[@]}"
  "${RTMINI_LAUNCH[@]}" "$exe" "${RTMINI_ARGS[@]}"
  summaries+=("$RTMINI_OUTDIR/strong-$r.json")
done
rtmini_python_tool scaling --mode strong -o "$RTMINI_OUTDIR/strong_scaling.png" "${summaries[@]}"
