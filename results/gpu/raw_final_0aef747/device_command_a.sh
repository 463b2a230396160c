# Device call A of two (same machine): CUDA build of every target of the repository root (the
# session's trial merge) and, beside it, main's sketchtrace (.carry/src_main.tgz) as the baseline.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit_trial.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
(mkdir -p /tmp/s_main && tar -xzf .carry/src_main.tgz -C /tmp/s_main && ln -sfn $PWD/inputs/meshes /tmp/s_main/inputs/meshes && cd /tmp/s_main &&
 cmake -S . -B b "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_main.log 2>&1 &&
 cmake --build b -j 4 --target sketchtrace > $OUT/build_main.log 2>&1; echo "main sketchtrace build rc=$? $(( $(date +%s)-t0 )) s") &
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
cmake --build build-cuda -j 13 -- -k 0 > $OUT/build_cuda.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build_cuda.log | head -40
wait
echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
