# Final device call A (issue 21): CUDA build of the session's trial merge (repository root):
# the bench and the core unit tests; beside it main's bench (.carry/src_main.tgz).
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit_trial.txt) main $(cat .carry/commit_main.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
(mkdir -p /tmp/s_main && tar -xzf .carry/src_main.tgz -C /tmp/s_main && rm -rf /tmp/s_main/inputs/meshes && ln -sfn $PWD/inputs/meshes /tmp/s_main/inputs/meshes && cd /tmp/s_main &&
 cmake -S . -B b "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_main.log 2>&1 &&
 cmake --build b -j 4 --target rtmini-bvh-bench -- -k 0 > $OUT/build_main.log 2>&1; echo "main bench build rc=$? $(( $(date +%s)-t0 )) s") &
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
timeout ${BLIM:-520} cmake --build build-cuda -j 12 --target rtmini-bvh-bench rtmini_unit_core_cuda -- -k 0 > $OUT/build_cuda.log 2>&1; echo "trial build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build_cuda.log | head -40; tail -2 $OUT/build_cuda.log
wait
echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|OUT|OUT|g" 2>/dev/null
