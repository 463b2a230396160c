#!/bin/bash
# (The exploration build: main 2354370 with raw_cpu15/explore_env.diff applied; the committed
# code has neither environment variable.)
# Issue 22 (branch cpu15): variants of the SAH's leaf term, alternated with main's bench in the same
# minutes. Each variant is "name:VAR=value,VAR=value" (the exploration build's RTMINI_SAH_BLOCK,
# RTMINI_WIDE_FULL, RTMINI_WIDE_COMPACT).
# Usage: BASE=<main's bench> BRANCH=<this branch's bench> OUT=<dir> RUNS=3 MESHES=".." WORKLOADS=".."
#        VARIANTS="b1:RTMINI_SAH_BLOCK=1 b4:RTMINI_SAH_BLOCK=4" results/bvh/raw_cpu15/explore.sh
cd "$(dirname "$0")/../../.."
export OMP_NUM_THREADS=2 OMP_PROC_BIND=false
for i in $(seq 1 "${RUNS:-3}"); do
  for m in ${MESHES:-dragon stanford-bunny}; do
    for w in ${WORKLOADS:-ao diffuse}; do
      args=""; [ "$w" = ao ] && args="--samples-per-face 1 --rays 16"
      list="base $VARIANTS"
      [ $((i % 2)) = 0 ] && list="$(echo $list | tr ' ' '\n' | tac | tr '\n' ' ')"
      for v in $list; do
        name=${v%%:*}
        f="$OUT/${m}_${w}_${name}_run$i.txt"
        { echo "date: $(date -u +%FT%TZ) uptime: $(uptime)"
          if [ "$name" = base ]; then
            echo "command: nice $BASE inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5"
            nice "$BASE" inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5 2>&1
          else
            envs=$(echo "${v#*:}" | tr ',' ' ')
            echo "command: env $envs nice $BRANCH inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5"
            env $envs nice "$BRANCH" inputs/meshes/$m.obj --workload $w $args --peer embree --repeats 5 2>&1
          fi
          echo "uptime after: $(uptime)"; } > "$f"
      done
    done
  done
done
echo done
