#!/bin/bash
# Final figures: for each mesh and workload, the branch's bench and the pre-change bench (1d174a7), each
# against Embree in the same process, 5 paired repeats, 2 threads. Alternated per workload.
cd "$(dirname "$0")/../../.."
out=results/bvh/raw_cputrav
export OMP_NUM_THREADS=2 OMP_PROC_BIND=false
for m in dragon stanford-bunny; do
  for w in ao shadow primary diffuse; do
    for v in after before; do
      bin=build/bench/rtmini-bvh-bench; [ $v = before ] && bin=${BEFORE_BENCH:?path to rtmini-bvh-bench built at 1d174a7}
      f=$out/${m}_${w}_${v}.txt
      { echo "command: OMP_NUM_THREADS=2 OMP_PROC_BIND=false nice $( [ $v = before ] && echo 'build(1d174a7)' || echo 'build(HEAD)' )/bench/rtmini-bvh-bench inputs/meshes/$m.obj --workload $w --peer embree --repeats 5"
        echo "commit: $( [ $v = before ] && echo 1d174a7 || git rev-parse --short HEAD )  date: $(date -u +%FT%TZ)"
        echo "uptime before: $(uptime)"
        nice $bin inputs/meshes/$m.obj --workload $w --peer embree --repeats 5 2>&1
        echo "uptime after: $(uptime)"; } > $f
    done
  done
done
echo done
