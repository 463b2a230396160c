#!/usr/bin/env bash
# Device call for issue 21's traversal goal (branch gputrav): the any-hit kernel variants of
# common/include/rtmini/bvh/any_hit_gpu.hpp, measured against today's kernel (--gpu-trace
# default) in the same run with the same binary. Steps: CUDA build of the bench and the core
# unit tests, unit.core.cuda (the new AnyHitKernels* tests trace every variant against brute
# force and the binary traversal on the device), then rtmini-bvh-bench AO on dragon and bunny,
# SAH and LBVH, every variant x ray order; then ncu of default and of the
# variant with the best dragon SAH rate (each bench run: best of 3 timed passes; the variants of
# one mesh and build run back to back). Outputs under $OUT (or /tmp/gputrav_out).
# Phases, so each fits one device command (<= 10 min; the build stays on a warm machine):
#   bash results/gpu/gputrav_device.sh build   # configure, build, unit.core.cuda (~5 min)
#   bash results/gpu/gputrav_device.sh bench   # 72 bench runs (~4 min)
#   bash results/gpu/gputrav_device.sh ncu [KERNEL ORDER]  # ncu of default and of KERNEL ORDER
#                                              # (default: the best dragon SAH run of `bench`)
#   bash results/gpu/gputrav_device.sh         # all three
#
# Run from the root of a checkout of the branch on the device machine, after the Kokkos CUDA
# environment of docs/cuda.md is set up (the coordinator's .carry/dev_env.sh defines deps_flags
# and PATH; Kokkos CUDA in /opt/kokkos-cuda), as in the phases above.
# Expected verification hashes (CUDA): dragon AO 65f36ebef7cd2ba5, bunny AO 7aba1e15a4309959,
# the same for every variant and ray order (the hash sums over ray indices, order-free).
set -u
phase=${1:-all}
[ -f .carry/dev_env.sh ] && source .carry/dev_env.sh
[ -n "${deps_flags+x}" ] || deps_flags=()
export OMP_PROC_BIND=false
OUT=${OUT:-/tmp/gputrav_out}; mkdir -p "$OUT"
t0=$(date +%s)
{
  echo "commit $(git rev-parse HEAD 2>/dev/null || echo unknown)"
  date -u
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
} > "$OUT/provenance.txt"
B=build-cuda
if [ "$phase" != bench ]; then
cmake -S . -B $B "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ \
  -DCMAKE_BUILD_TYPE=Release > "$OUT/cfg.log" 2>&1 || tail -30 "$OUT/cfg.log"
cmake --build $B -j 16 --target rtmini-bvh-bench rtmini_unit_core_cuda > "$OUT/build.log" 2>&1
echo "build rc=$? $(($(date +%s) - t0)) s"
grep -E 'error' -A3 "$OUT/build.log" | head -40
(cd $B && timeout 240 ctest -R 'unit.core.cuda' --output-on-failure --timeout 230 > "$OUT/unit_core_cuda.txt" 2>&1
 echo "unit.core.cuda rc=$? $(($(date +%s) - t0)) s"; tail -3 "$OUT/unit_core_cuda.txt")
fi
[ "$phase" = build ] && exit 0

if [ "$phase" != ncu ]; then
L=$OUT/bench.txt
bench() {  # mesh quality kernel order
  echo "== $1 $2 $3 $4" >> "$L"
  timeout 60 $B/bench/rtmini-bvh-bench inputs/meshes/$1.obj --workload ao --quality "$2" \
    --gpu-trace "$3" --ray-order "$4" >> "$L" 2>&1
  echo "rc=$?" >> "$L"
}
KERNELS="default wide stored short8 short16"
for m in dragon stanford-bunny; do
  for q in sah lbvh; do
    for order in ray coherent; do
      for k in $KERNELS; do bench $m $q $k $order; done
    done
  done
done
echo "bench done $(($(date +%s) - t0)) s"
# One line per run: mesh quality kernel order Mrays/s hash.
awk '/^== /{tag=$2" "$3" "$4" "$5} /^FOM/{print tag, $2, $NF}' "$L" | sort -k1,4 -s | tee "$OUT/summary.txt"
best=$(awk '$1=="dragon" && $2=="sah" {s[$3" "$4]+=$5; c[$3" "$4]++}
            END {for (k in s) print s[k]/c[k], k}' "$OUT/summary.txt" | sort -gr | head -1)
echo "best on dragon SAH (mean Mrays/s, kernel, order): $best"
echo "$best" > $B/gputrav_best.txt  # for a later `ncu` call on the same (warm) machine
cp "$OUT/summary.txt" $B/gputrav_summary.txt
fi
[ "$phase" = bench ] && exit 0

if [ $# -ge 3 ]; then pick="$2 $3"
elif [ -f $B/gputrav_best.txt ]; then pick=$(cut -d' ' -f2,3 $B/gputrav_best.txt)
else pick="short8 ray"; fi
# Registers and local memory of each kernel, and ncu counters of the AO trace kernel.
cuobjdump --dump-resource-usage $B/bench/rtmini-bvh-bench > "$OUT/resources.txt" 2>&1
M=launch__registers_per_thread,l1tex__t_sectors_pipe_lsu_mem_local_op_ld.sum,l1tex__t_sectors_pipe_lsu_mem_local_op_st.sum,smsp__thread_inst_executed_per_inst_executed.ratio,sm__warps_active.avg.pct_of_peak_sustained_active,gpu__time_duration.sum,l1tex__throughput.avg.pct_of_peak_sustained_active
for kv in "default ray" "$pick"; do
  set -- $kv
  timeout 150 ncu --clock-control none --metrics $M --csv \
    $B/bench/rtmini-bvh-bench inputs/meshes/dragon.obj --workload ao --quality sah \
    --gpu-trace "$1" --ray-order "$2" --repeats 1 > "$OUT/ncu_$1_$2.csv" 2>&1
  echo "ncu $1 $2 rc=$? $(($(date +%s) - t0)) s"
  python3 results/gpu/raw_qwide/ncu_summary.py "$OUT/ncu_$1_$2.csv" > "$OUT/ncu_$1_$2_summary.txt" 2>&1
  cat "$OUT/ncu_$1_$2_summary.txt"
done
echo "total $(($(date +%s) - t0)) s"
