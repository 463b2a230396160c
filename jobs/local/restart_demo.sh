#!/usr/bin/env bash
# Checkpoint/restart on one machine: run with a short --time-limit, rerun with
# --restart while the app exits 4, then compare against an uninterrupted run
# (the run contract promises identical output).
# Usage: jobs/local/restart_demo.sh [OUTDIR]
# Environment (defaults in brackets):
#   RTMINI_RANKS           ranks [2]
#   RTMINI_THREADS         OpenMP threads per rank [1]
#   RTMINI_TIME_LIMIT_MIN  --time-limit per segment, minutes [0.05]
#   RTMINI_CHAIN_MAX       most segments before giving up [50]
#   RTMINI_OUTDIR          outputs, overridden by OUTDIR [$PWD/rtmini-restart]
#   RTMINI_BUILD RTMINI_BIN RTMINI_APP RTMINI_INPUT and the app knobs: see jobs/lib/rtmini_job.sh
# Exit: 0 identical outputs, 1 they differ or the chain failed.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# shellcheck source=SCRIPTDIR/../lib/rtmini_job.sh
. "$here/../lib/rtmini_job.sh"
RTMINI_OUTDIR=${1:-${RTMINI_OUTDIR:-$PWD/rtmini-restart}}
rtmini_init "$(cd "$here/../.." && pwd)"
exe=$(rtmini_binary "$RTMINI_APP")
rtmini_mpirun_launcher "${RTMINI_RANKS:-2}" "${RTMINI_THREADS:-1}"
max=${RTMINI_CHAIN_MAX:-50}
ckpt=$RTMINI_OUTDIR/chained.ckpt.h5
rm -f "$ckpt"

count=1
while :; do
  RTMINI_TAG=chained
  rtmini_app_args
  rtmini_checkpoint_args "$ckpt" "${RTMINI_TIME_LIMIT_MIN:-0.05}"
  rtmini_banner "${RTMINI_LAUNCH[@]}" "$exe" "${RTMINI_ARGS[@]}"
  rc=0
  "${RTMINI_LAUNCH[@]}" "$exe" "${RTMINI_ARGS[@]}" || rc=$?
  case $(rtmini_chain_decision "$rc" "$count" "$max" "$ckpt") in
    done) break ;;
    resubmit) echo "restart_demo: segment $count checkpointed, restarting"; count=$((count + 1)) ;;
    *) echo "restart_demo: segment $count failed (exit $rc)" >&2; exit 1 ;;
  esac
done

RTMINI_TAG=uninterrupted
rtmini_app_args
"${RTMINI_LAUNCH[@]}" "$exe" "${RTMINI_ARGS[@]}"
ext=png
[ "$RTMINI_APP" = bake ] && ext=bs
[ "$RTMINI_APP" = sketchtrace ] && ext=${RTMINI_IMAGE_EXT:-png}
if cmp -s "$RTMINI_OUTDIR/chained.$ext" "$RTMINI_OUTDIR/uninterrupted.$ext"; then
  echo "restart_demo: $count segment(s); output identical to the uninterrupted run"
else
  echo "restart_demo: $count segment(s); output DIFFERS from the uninterrupted run" >&2
  exit 1
fi
