#!/bin/bash
# Issue 22 (branch cputrav2): main's bench and this branch's, alternated, on the issue's command.
# For each run index (outer loop, so the runs spread over the session's load), mesh and workload,
# both benches trace the same rays with rtmini and Embree pass by pass (5 paired repeats, 2
# threads); odd runs start with main's bench, even runs with the branch's. AO uses the dev size
# (`--samples-per-face 1 --rays 16`, the issue's distribution, 1/12 of the rays) as in raw_cpu22.
# Usage: BASE=/path/to/main/rtmini-bvh-bench BASE_COMMIT=<main's commit> [BRANCH=/path/to/copy]
#        [OUT=FOLDER] results/bvh/raw_cputrav2/run.sh [FIRST_RUN] [LAST_RUN]   (issue 22, cputrav2 and cputrav3)
# (BASE: a copy of main's bench binary; BRANCH: a copy of this branch's, build/bench's by default,
# so that building during the runs does not swap it.)
cd "$(dirname "$0")/../../.."
out=${OUT:-results/bvh/raw_cputrav2}
first=${1:-1}
last=${2:-5}
workloads=${WORKLOADS:-ao shadow primary diffuse}
branch=${BRANCH:-build/bench/rtmini-bvh-bench}
export OMP_NUM_THREADS=2 OMP_PROC_BIND=false
run_one() {  # which binary mesh workload run
  local which=$1 bin=$2 m=$3 w=$4 i=$5 args="" name=$4 commit
  if [ "$w" = ao ]; then args="--samples-per-face 1 --rays 16"; name=ao_small; fi
  if [ "$which" = main ]; then commit=${BASE_COMMIT:-?}; else commit=${BRANCH_COMMIT:-$(git rev-parse --short HEAD)}; fi
  { echo "command: OMP_NUM_THREADS=2 OMP_PROC_BIND=false nice $bin inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5"
    echo "bench: $which  commit: $commit  date: $(date -u +%FT%TZ)"
    echo "uptime before: $(uptime)"
    nice "$bin" inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5 2>&1
    echo "uptime after: $(uptime)"; } > "$out/${m}_${name}_${which}_run$i.txt"
}
for i in $(seq "$first" "$last"); do
  for m in dragon stanford-bunny; do
    for w in $workloads; do
      if [ $((i % 2)) = 1 ]; then
        run_one main "$BASE" $m $w $i; run_one branch "$branch" $m $w $i
      else
        run_one branch "$branch" $m $w $i; run_one main "$BASE" $m $w $i
      fi
    done
  done
done
echo done
