#!/usr/bin/env bash
# Device run for issue 21 (branch gpuany): every any-hit kernel of
# common/include/rtmini/bvh/any_hit_gpu.hpp (rtmini-bvh-bench --gpu-trace NAME) against today's
# kernel (`default`) with the same binary in one run, then ncu counters of each on dragon AO SAH.
#
# Usage (from the repository root, after a CUDA build of rtmini-bvh-bench into BUILD_DIR):
#   bash results/gpu/anyhit_device.sh BUILD_DIR [bench|ncu|all]     (default: all)
# MESHES (default "dragon stanford-bunny", names under inputs/meshes) picks the bench's meshes,
# e.g. MESHES=CornellBox-Original for a quick check of the script on the host.
# Outputs under $OUT (default /tmp/anyhit_out): bench.txt (every run's output), summary.txt (one
# line per run: mesh quality kernel Mrays/s hash), ncu_<kernel>.csv, ncu_summary.txt,
# provenance.txt. Expected on CUDA: every kernel gives the default's verification hash per mesh
# (dragon AO 65f36ebef7cd2ba5, bunny AO 7aba1e15a4309959, any build).
#
# Bench phase: AO (3 samples x 64 cosine rays per triangle), dragon and bunny, SAH and LBVH, each
# kernel one run of 3 timed launches (the bench reports the best); the kernels of one mesh and
# build back to back. PASSES=2 runs the list a second time in reverse order (ABC..., ...CBA), so
# drift over the run falls on every kernel alike; anyhit_summary.py keeps a kernel's best run.
# 68 runs of ~3 s each on the H200 per pass of every kernel (~3.5 min).
# ncu phase (if ncu is on PATH): one run per kernel on dragon AO SAH, `--repeats 1` so the
# profiled launch is the timed one, `--launch-count 1` on the trace kernel only (~10 s each,
# ~2.5 min). With the CUDA build and unit.core.cuda in the same 10-minute call, run `bench` there
# and `ncu` in the next call on the warm machine if the first ran short of time.
set -u
B=${1:?usage: anyhit_device.sh BUILD_DIR [bench|ncu|all]}
phase=${2:-all}
BENCH=$B/bench/rtmini-bvh-bench
[ -x "$BENCH" ] || { echo "no $BENCH"; exit 3; }
export OMP_PROC_BIND=false
OUT=${OUT:-/tmp/anyhit_out}
mkdir -p "$OUT"
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
t0=$(date +%s)
{
  echo "commit $(git rev-parse HEAD 2>/dev/null || echo unknown)"
  date -u
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null
  "$BENCH" --help 2>/dev/null | grep -A2 -- '--gpu-trace' | head -3
} > "$OUT/provenance.txt"
# KERNELS (default: every kernel) picks a subset, e.g. KERNELS="default stored speculative";
# RUN_LIMIT (default 60) is the seconds one bench run may take (twice that under ncu).
KERNELS=${KERNELS:-"default stored short8 default_lb stored_lb shared8 shared16 compact compact_lb
  compact_shared16 speculative speculative_shared16 speculative_compact wide wide_lb wide_shared
  short16"}
REVERSED=$(echo $KERNELS | tr ' ' '\n' | tac | tr '\n' ' ')

if [ "$phase" != ncu ]; then
  L=$OUT/bench.txt
  : > "$L"
  for q in sah lbvh; do
    for m in ${MESHES:-dragon stanford-bunny}; do
      order=$KERNELS
      [ "${PASSES:-1}" = 2 ] && order="$KERNELS $REVERSED"
      for k in $order; do
        echo "== $m $q $k" >> "$L"
        timeout ${RUN_LIMIT:-60} "$BENCH" inputs/meshes/$m.obj --workload ao --quality $q \
          --gpu-trace $k >> "$L" 2>&1
        echo "rc=$?" >> "$L"
      done
      echo "$m $q done $(($(date +%s) - t0)) s"
    done
  done
  python3 "$here/anyhit_summary.py" bench "$L" | tee "$OUT/summary.txt"
fi

if [ "$phase" != bench ]; then
  if ! command -v ncu > /dev/null; then
    echo "no ncu on PATH: ncu phase skipped"
    exit 0
  fi
  M=launch__registers_per_thread,launch__block_size,launch__shared_mem_per_block_dynamic
  M=$M,l1tex__t_sectors_pipe_lsu_mem_local_op_ld.sum,l1tex__t_sectors_pipe_lsu_mem_local_op_st.sum
  M=$M,sm__warps_active.avg.pct_of_peak_sustained_active,smsp__thread_inst_executed_per_inst_executed.ratio
  M=$M,gpu__time_duration.sum,l1tex__throughput.avg.pct_of_peak_sustained_active
  for k in $KERNELS; do
    timeout $((2 * ${RUN_LIMIT:-60})) ncu --clock-control none --metrics $M --csv \
      --kernel-name-base demangled --kernel-name regex:AnyHitEachRay --launch-count 1 \
      "$BENCH" inputs/meshes/dragon.obj --workload ao --quality sah --gpu-trace $k --repeats 1 \
      > "$OUT/ncu_$k.csv" 2>&1
    echo "ncu $k rc=$? $(($(date +%s) - t0)) s"
  done
  python3 "$here/anyhit_summary.py" ncu "$OUT"/ncu_*.csv | tee "$OUT/ncu_summary.txt"
fi
echo "total $(($(date +%s) - t0)) s"
