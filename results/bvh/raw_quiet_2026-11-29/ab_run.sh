#!/bin/bash
# Issue 22's traversal rows, two benches alternated in one run (2026-11-29): STATIC (main before
# RayLoopPolicy, 81e98b3's bench) and DYNAMIC (0d054e7's), the issue's command five times per
# mesh and workload, runs outermost, odd runs static first. AO at the dev size, as trav_run.sh.
# Usage: STATIC=/path/bench DYNAMIC=/path/bench [AB_OUT=ab2] results/bvh/raw_quiet_2026-11-29/ab_run.sh
cd "$(dirname "$0")/../../.."
out=results/bvh/raw_quiet_2026-11-29/${AB_OUT:-ab}
mkdir -p "$out"
export OMP_NUM_THREADS=2 OMP_PROC_BIND=false
one() {  # name bench mesh workload run
  local args="" name=$4
  if [ "$4" = ao ]; then args="--samples-per-face 1 --rays 16"; name=ao_small; fi
  { echo "command: $2 inputs/meshes/$3.obj --workload $4 $args --peer embree --repeats 5"
    echo "bench: $1  date: $(date -u +%FT%TZ)  uptime: $(uptime)"
    "$2" inputs/meshes/$3.obj --workload $4 $args --peer embree --repeats 5 2>&1
  } > "$out/${3}_${name}_${1}_run$5.txt"
}
for i in 1 2 3 4 5; do
  for m in dragon stanford-bunny; do
    for w in ao shadow primary diffuse; do
      if [ $((i % 2)) = 1 ]; then one static "$STATIC" $m $w $i; one dynamic "$DYNAMIC" $m $w $i
      else one dynamic "$DYNAMIC" $m $w $i; one static "$STATIC" $m $w $i; fi
    done
  done
done
