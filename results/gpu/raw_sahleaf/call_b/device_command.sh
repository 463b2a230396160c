# Call B: main + SahLeafCost (device SAH trees count single triangles) against 2354370's bench
# (before blocks of four) and 81e98b3's (blocks of four on devices too), built in call A.
set -u
source .carry/dev_cuda.sh
t0=$(date +%s); el() { echo "[$(($(date +%s)-t0)) s] $*"; }
{ cat .carry/commit.txt; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
build_kokkos_cuda || exit 1; el kokkos
mkdir -p /tmp/a && tar xzf .carry/benches-a.tgz -C /tmp/a
cuda_configure /tmp/b $R -DRTMINI_ENABLE_TESTS=ON > /tmp/cfg.log 2>&1 || tail -20 /tmp/cfg.log
cmake --build /tmp/b -j 16 --target rtmini-bvh-bench > /tmp/bn.log 2>&1 || grep -m5 -A8 error /tmp/bn.log; el bench
(cmake --build /tmp/b -j 16 --target rtmini_unit_core_cuda > /tmp/bu.log 2>&1; echo "unit build rc=$?" > /tmp/unit_build_rc) &
ub=$!
N=/tmp/b/bench/rtmini-bvh-bench; O=/tmp/a/bench-old; P=/tmp/a/bench-new
for r in 1 2; do for m in dragon stanford-bunny; do for b in $O $N $P; do
  echo "== $r $m $b sah"; timeout 60 $b inputs/meshes/$m.obj --workload ao --quality sah --time-builds sah --repeats 3 2>&1 | grep -E "FOM|traced with"
done; done; done > $OUT/ao_sah.txt 2>&1
el ao; grep -E "==|FOM" $OUT/ao_sah.txt
for m in dragon; do for b in $O $N; do
  echo "== 10x $m $b sah"; timeout 90 $b inputs/meshes/$m.obj --copies 10 --workload ao --quality sah --time-builds sah --samples-per-face 1 --repeats 3 2>&1 | grep -E "FOM|traced with"
done; done > $OUT/ao_sah_1m.txt 2>&1; cat $OUT/ao_sah_1m.txt
wait $ub; cat /tmp/unit_build_rc; el unit built
if [ -x /tmp/b/tests/unit/rtmini_unit_core_cuda ]; then
  (cd /tmp/b && timeout $((580 - ($(date +%s)-t0))) ./tests/unit/rtmini_unit_core_cuda > $OUT/unit_core_cuda.txt 2>&1; echo "unit rc=$?"; grep -E "SahBuild|FAILED|PASSED" $OUT/unit_core_cuda.txt | tail -5)
fi
el end
