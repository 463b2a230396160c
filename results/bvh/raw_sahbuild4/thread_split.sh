#!/usr/bin/env bash
# Where a 2-thread SAH build's CPU time goes, per thread (issue 22, build row, branch sahbuild4):
# perf samples (cpu-clock, 4 kHz) of a whole --build-only run of 30 SAH builds with
# OMP_WAIT_POLICY=passive (so an idle thread sleeps instead of spinning and its samples are
# work), per thread, for BEFORE and AFTER alternately. The main thread also runs everything
# outside the builds (the same in both). On a quiet 2-core machine the build's wall time is at
# least the main thread's share, so a share moved to the worker is wall time saved there; the
# shared machine's wall clock cannot show it.
# Usage: thread_split.sh BEFORE_BENCH AFTER_BENCH [runs] > thread_split.txt
set -uo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../../.." && pwd)
before=$1 after=$2 runs=${3:-5}
data=$(mktemp)
export OMP_PROC_BIND=false OMP_WAIT_POLICY=passive
for mesh in dragon stanford-bunny; do
  for _ in $(seq "$runs"); do
    for b in "$before" "$after"; do
      perf record -q -e cpu-clock -F 4000 -o "$data" "$b" "$root/inputs/meshes/$mesh.obj" --build-only \
        --time-builds sah --repeats 30 --threads 2 >/dev/null 2>&1
      # Samples per thread of the bench's process, most first: main thread, then the worker.
      counts=$(perf report -i "$data" --no-children --sort pid -n --stdio 2>/dev/null |
        grep "$(basename "$b")" | awk '{print $2}' | head -2 | tr '\n' ' ')
      echo "$mesh $(basename "$b") samples main worker: $counts load $(cut -d' ' -f1 /proc/loadavg)"
    done
  done
done
rm -f "$data"
