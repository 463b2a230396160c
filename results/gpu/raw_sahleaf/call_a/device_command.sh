# Call A: Kokkos CUDA, main's bench and the pre-block-of-four bench (2354370), unit_core_cuda.
set -u
source .carry/dev_cuda.sh
t0=$(date +%s); el() { echo "[$(($(date +%s)-t0)) s] $*"; }
{ cat .carry/commit.txt; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; nproc; } > $OUT/provenance.txt
build_kokkos_cuda || exit 1; el kokkos
(cd $KCUDA && tar czf $OUT/kokkos-cuda-install.tgz .) ; ls -la $OUT/kokkos-cuda-install.tgz
mkdir -p /tmp/old && tar xzf .carry/old-src.tgz -C /tmp/old && ln -s $R/inputs/meshes /tmp/old/inputs/meshes
cuda_configure /tmp/b-new $R -DRTMINI_ENABLE_TESTS=ON > /tmp/cfg-new.log 2>&1 || tail -20 /tmp/cfg-new.log
cuda_configure /tmp/b-old /tmp/old -DRTMINI_ENABLE_TESTS=OFF > /tmp/cfg-old.log 2>&1 || tail -20 /tmp/cfg-old.log
el configured
cmake --build /tmp/b-new -j 16 --target rtmini-bvh-bench > /tmp/bn.log 2>&1 || grep -m5 -A8 error /tmp/bn.log; el bench new
cmake --build /tmp/b-old -j 16 --target rtmini-bvh-bench > /tmp/bo.log 2>&1 || grep -m5 -A8 error /tmp/bo.log; el bench old
strip -o /tmp/bench-new /tmp/b-new/bench/rtmini-bvh-bench; strip -o /tmp/bench-old /tmp/b-old/bench/rtmini-bvh-bench
tar czf $OUT/benches.tgz -C /tmp bench-new bench-old; ls -la $OUT/
B=/tmp/bench-new; O=/tmp/bench-old
for r in 1 2; do for m in dragon stanford-bunny; do for b in $O $B; do
  echo "== $r $m $(basename $b) sah default"; timeout 60 $b inputs/meshes/$m.obj --workload ao --quality sah --time-builds sah --repeats 3 2>&1 | grep -E "FOM|hash|nodes|Grays|Mrays" | head -8
done; done; done > $OUT/ao_sah.txt 2>&1
el ao; cat $OUT/ao_sah.txt | grep -E "==|FOM" 
timeout $((560 - ($(date +%s)-t0))) cmake --build /tmp/b-new -j 16 --target rtmini_unit_core_cuda > /tmp/bu.log 2>&1; el unit build rc=$?
if [ -x /tmp/b-new/tests/unit/rtmini_unit_core_cuda ]; then
  (cd /tmp/b-new && timeout $((590 - ($(date +%s)-t0))) ./tests/unit/rtmini_unit_core_cuda > $OUT/unit_core_cuda.txt 2>&1; echo "unit rc=$?"; tail -3 $OUT/unit_core_cuda.txt)
fi
el end
