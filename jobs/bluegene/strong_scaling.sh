#!/usr/bin/env bash
# Strong scaling on Blue Gene/Q under Cobalt: one run.qsub job per node count,
# same problem each time. Usage (from the repository root):
#   RTMINI_QSUB_ARGS="-A PROJECT" jobs/bluegene/strong_scaling.sh
# Environment (defaults in brackets), plus everything run.qsub reads:
#   RTMINI_NODES           node counts (BG/Q blocks: 32 and up on most machines) ["32 64 128 256 512"]
#   RTMINI_RANKS_PER_NODE  [16]
#   RTMINI_MINUTES         wall-clock minutes per job (queue limit) [30]
#   RTMINI_OUTDIR          outputs [$PWD/rtmini-bgq-strong]; tags strong-<ranks>
#   RTMINI_QSUB_ARGS       extra qsub options, e.g. "-A PROJECT -q prod" []
# Prints the Cobalt job ids; afterwards plot with
#   cd analysis && /usr/bin/python3 -m rtmini_analysis.scaling OUTDIR/strong-*.json -o strong.png
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=${RTMINI_ROOT:-$(cd "$here/../.." && pwd)}
outdir=${RTMINI_OUTDIR:-$PWD/rtmini-bgq-strong}
rpn=${RTMINI_RANKS_PER_NODE:-16}
read -r -a extra <<<"${RTMINI_QSUB_ARGS:-}"
mkdir -p "$outdir"

for n in ${RTMINI_NODES:-32 64 128 256 512}; do
  ranks=$((n * rpn))
  (cd "$root" && qsub "${extra[@]}" -n "$n" -t "${RTMINI_MINUTES:-30}" --mode script \
    -O "$outdir/strong-$ranks" \
    --env "RTMINI_ROOT=$root:RTMINI_OUTDIR=$outdir:RTMINI_TAG=strong-$ranks:RTMINI_RANKS_PER_NODE=$rpn" \
    "$root/jobs/bluegene/run.qsub")
done
