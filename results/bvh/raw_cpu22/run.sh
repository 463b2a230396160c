#!/bin/bash
# Issue 22 figures: five runs of the issue's command for each mesh and workload (the run index is
# the outer loop, so the runs of one combination are spread over the session's load), each run
# tracing the same rays with rtmini and Embree pass by pass (5 paired repeats), 2 threads.
# The AO workload is the issue's (19.2M rays on the dragon) unless AO_ARGS is set: five runs of
# it take ~35 min here under load, so run 1 used it and runs 2-5 (and run 1 again, as
# ao_small) used AO_ARGS="--samples-per-face 1 --rays 16" (same rays' distribution, 1/12 of them).
# Usage: [AO_ARGS=...] [WORKLOADS="ao shadow ..."] results/bvh/raw_cpu22/run.sh [FIRST_RUN] [LAST_RUN]
cd "$(dirname "$0")/../../.."
out=results/bvh/raw_cpu22
first=${1:-1}
last=${2:-5}
workloads=${WORKLOADS:-ao shadow primary diffuse}
export OMP_NUM_THREADS=2 OMP_PROC_BIND=false
for i in $(seq "$first" "$last"); do
  for m in dragon stanford-bunny; do
    for w in $workloads; do
      args=""
      name=$w
      if [ "$w" = ao ] && [ -n "${AO_ARGS:-}" ]; then args=$AO_ARGS; name=ao_small; fi
      f=$out/${m}_${name}_run$i.txt
      { echo "command: OMP_NUM_THREADS=2 OMP_PROC_BIND=false nice build/bench/rtmini-bvh-bench inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5"
        echo "commit: $(git rev-parse --short HEAD)  date: $(date -u +%FT%TZ)"
        echo "uptime before: $(uptime)"
        nice build/bench/rtmini-bvh-bench inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5 2>&1
        echo "uptime after: $(uptime)"; } > "$f"
    done
  done
done
echo done
