# Device call B: the unit-labelled ctests on call A's CUDA build (the machine still warm).
source .carry/dev_env.sh
t0=$(date +%s)
[ -d build-cuda ] || { echo "no build-cuda: the machine was not warm"; exit 1; }
cmake --build build-cuda -j 16 -- -k 0 > $OUT/build_cuda_b.log 2>&1; echo "cuda build (incremental) rc=$? $(( $(date +%s)-t0 )) s"
(cd build-cuda && timeout 560 ctest -L unit --timeout 540 -j 8 > $OUT/unit_cuda.txt 2>&1; echo "ctest rc=$? $(( $(date +%s)-t0 )) s"; grep -E "tests passed|Failed|Not Run|\(Failed\)|Skipped|Timeout" $OUT/unit_cuda.txt | head -20)
sed -i "s|$(pwd)|.|g" $OUT/unit_cuda.txt
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
