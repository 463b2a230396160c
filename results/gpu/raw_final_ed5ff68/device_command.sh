# Device call: CUDA build of every target of the repository root (the session's final merge) and
# its unit-labelled ctests (docs/cuda.md's recipe; Kokkos 4.6.99 CUDA from .carry).
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit_trial.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
cmake --build build-cuda -j 16 -- -k 0 > $OUT/build_cuda.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build_cuda.log | head -30
(cd build-cuda && timeout 330 ctest -L unit --timeout 300 -j 8 > $OUT/unit_cuda.txt 2>&1; echo "ctest rc=$? $(( $(date +%s)-t0 )) s"; grep -E "tests passed|Failed|Not Run|\(Failed\)|Skipped" $OUT/unit_cuda.txt | head -20)
sed -i "s|$(pwd)|.|g" $OUT/unit_cuda.txt
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
