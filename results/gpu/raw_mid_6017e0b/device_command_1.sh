# Device call 1 of 2 (issue 21, mid-session): CUDA build of the trial merge of gpusketch + gpuany
# (the repository root) for the bench, sketchtrace and the core unit tests, and main's sketchtrace
# (.carry/src_main.tgz) as the in-run baseline; then unit.core.cuda and sketchtrace before/after.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit_trial.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
(mkdir -p /tmp/s_main && tar -xzf .carry/src_main.tgz -C /tmp/s_main && ln -sfn $PWD/inputs/meshes /tmp/s_main/inputs/meshes && cd /tmp/s_main &&
 cmake -S . -B b "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_main.log 2>&1 &&
 cmake --build b -j 5 --target sketchtrace > $OUT/build_main.log 2>&1; echo "main sketchtrace build rc=$? $(( $(date +%s)-t0 )) s") &
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
cmake --build build-cuda -j 12 --target rtmini-bvh-bench sketchtrace rtmini_unit_core_cuda -- -k 0 > $OUT/build_cuda.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build_cuda.log | head -40
wait
(cd build-cuda && timeout 150 ctest -R unit.core.cuda --timeout 140 > $OUT/unit_core_cuda.txt 2>&1; echo "unit.core.cuda rc=$? $(( $(date +%s)-t0 )) s"; grep -E "tests passed|Failed" $OUT/unit_core_cuda.txt)
mkdir -p $OUT/sketch
OUT=$OUT/sketch timeout ${SKLIM:-200} bash results/gpu/sketchtrace_device.sh build-cuda /tmp/s_main/b > $OUT/sketch.txt 2>&1; echo "sketch rc=$? $(( $(date +%s)-t0 )) s"; tail -25 $OUT/sketch.txt
echo "total $(( $(date +%s)-t0 )) s"
rm -f $OUT/sketch/*.png
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
