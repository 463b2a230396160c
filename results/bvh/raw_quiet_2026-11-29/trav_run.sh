#!/bin/bash
# Issue 22's traversal rows on a quiet machine (2026-11-29): main's bench alone, the issue's
# command five times per mesh and workload (runs outermost), as raw_cputrav2/run.sh does for one
# binary. AO at the dev size (--samples-per-face 1 --rays 16), as there.
# Usage: BENCH=/path/to/rtmini-bvh-bench [TRAV_OUT=trav2] results/bvh/raw_quiet_2026-11-29/trav_run.sh
cd "$(dirname "$0")/../../.."
out=results/bvh/raw_quiet_2026-11-29/${TRAV_OUT:-trav}
mkdir -p "$out"
export OMP_NUM_THREADS=2 OMP_PROC_BIND=false
for i in 1 2 3 4 5; do
  for m in dragon stanford-bunny; do
    for w in ao shadow primary diffuse; do
      args=""; name=$w
      if [ "$w" = ao ]; then args="--samples-per-face 1 --rays 16"; name=ao_small; fi
      { echo "command: $BENCH inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5"
        echo "commit: $(git rev-parse --short HEAD)  date: $(date -u +%FT%TZ)  uptime: $(uptime)"
        "$BENCH" inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5 2>&1
      } > "$out/${m}_${name}_run$i.txt"
    done
  done
done
