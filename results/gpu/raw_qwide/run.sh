#!/usr/bin/env bash
# Device call (issue 21): CUDA builds of main (the in-run baseline, built from the device copy's
# root) and of the gpu branch (copied to .gpuwt), the core unit ctests on CUDA, then the bench
# and the AO whole bake, baseline and branch interleaved. Run from the device copy's root:
#   bash .gpuwt/results/gpu/raw_qwide/run.sh   (outputs in $OUT)
set -u
source .carry/dev_env.sh
export OMP_PROC_BIND=false
R=/tmp/r; mkdir -p $R
pack() { tar -C /tmp -czf $OUT/qwide.tgz r; }
t0=$(date +%s)
{
  echo "branch gpu commit $(cat .gpuwt/.commit)"
  echo "baseline main commit $(cat .gpuwt/.base_commit)"
  date -u
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
  ls /usr/local/cuda/bin | tr '\n' ' '
} > $R/provenance.txt
cfg() { cmake -S "$1" -B "$2" "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > "$R/cfg_$3.log" 2>&1; }
(cfg . build-base base && cmake --build build-base -j 6 --target rtmini-bvh-bench bake > $R/build_base.log 2>&1
 echo "base build rc=$? $(( $(date +%s) - t0 )) s") &
(cfg .gpuwt .gpuwt/build-cuda new && cmake --build .gpuwt/build-cuda -j 10 --target rtmini-bvh-bench bake rtmini_unit_core_cuda > $R/build_new.log 2>&1
 echo "new build rc=$? $(( $(date +%s) - t0 )) s") &
wait
grep -h 'error' $R/build_base.log $R/build_new.log | head -20
B=build-base; N=.gpuwt/build-cuda
(cd $N && timeout 200 ctest -R 'unit.core.cuda' --output-on-failure --timeout 190 > $R/unit_core_cuda.txt 2>&1; echo "unit.core.cuda rc=$? $(( $(date +%s) - t0 )) s"; tail -3 $R/unit_core_cuda.txt) &
TESTPID=$!
wait $TESTPID
pack
L=$R/bench.txt
bench() { local tag=$1 bin=$2; shift 2; echo "== $tag: $*" >> $L; timeout 90 $bin/bench/rtmini-bvh-bench "$@" >> $L 2>&1; echo "rc=$?" >> $L; }
for rep in 1 2; do
  for m in dragon stanford-bunny; do
    for q in sah lbvh; do
      bench base $B inputs/meshes/$m.obj --workload ao --quality $q
      bench new $N inputs/meshes/$m.obj --workload ao --quality $q
    done
  done
  bench base $B inputs/meshes/dragon.obj --workload diffuse --quality sah
  bench new $N inputs/meshes/dragon.obj --workload diffuse --quality sah
done
bench base $B icosphere:8 --workload ao --quality lbvh --samples-per-face 1 --rays 16
bench new $N icosphere:8 --workload ao --quality lbvh --samples-per-face 1 --rays 16
pack; echo "bench done $(( $(date +%s) - t0 )) s"
grep -E '^== |FOM|build:|per ray' $L | head -80
for rep in 1 2; do
  for t in base new; do
    bin=$B; [ $t = new ] && bin=$N
    echo "== ao_whole $t rep $rep" >> $R/ao.txt
    timeout 60 $bin/miniapps/bake/bake ao inputs/ao/dragon_x4.toml -s 1250000 -o /tmp/d_$t.glb --summary $R/ao_${t}_$rep.json >> $R/ao.txt 2>&1
  done
done
grep -E '^==|bake|rays|hash' $R/ao.txt | head -40
# Registers, stack frame and local memory of each kernel, and ncu counters of the AO trace.
for t in base new; do
  bin=$B; [ $t = new ] && bin=$N
  cuobjdump --dump-resource-usage $bin/bench/rtmini-bvh-bench > $R/resources_$t.txt 2>&1
  M=launch__registers_per_thread,l1tex__t_sectors_pipe_lsu_mem_local_op_ld.sum,l1tex__t_sectors_pipe_lsu_mem_local_op_st.sum,smsp__thread_inst_executed_per_inst_executed.ratio,sm__warps_active.avg.pct_of_peak_sustained_active,gpu__time_duration.sum,l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum,l1tex__throughput.avg.pct_of_peak_sustained_active,dram__throughput.avg.pct_of_peak_sustained_elapsed
  [ "${NCU_BASE:-0}" = 1 ] || [ $t = new ] || continue
  timeout 150 ncu --clock-control none --metrics $M --csv $bin/bench/rtmini-bvh-bench inputs/meshes/dragon.obj --workload ao --quality sah --repeats 1 > $R/ncu_$t.csv 2>&1
  echo "ncu $t rc=$? $(( $(date +%s) - t0 )) s"
done
pack; echo "total $(( $(date +%s) - t0 )) s"
