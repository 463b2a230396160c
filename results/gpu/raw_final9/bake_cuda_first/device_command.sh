# Call 4: the trial's bake on CUDA (bake10's device paths: packed exchange messages, shared
# layout tables): build bake + its test programs, then the rank-count, decomposition, restart and
# hemisphere checks and unit.bake on the CUDA backend.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
cuda_configure build-cuda > $OUT/cfg.log 2>&1 || tail -30 $OUT/cfg.log
cmake --build build-cuda -j 16 --target bake rtmini-gen-inputs rtmini_unit_bake rtmini_unit_bsb > $OUT/build.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build.log | head -20
(cd build-cuda && timeout $(( 560 - ($(date +%s)-t0) )) ctest -R 'unit.bake$|bake.distributed|bake.decomposition|bake.restart.np|bake.hemisphere|bake.binary_output' --output-on-failure --timeout 120 > $OUT/ctest_bake_cuda.txt 2>&1); echo "ctest rc=$? $(( $(date +%s)-t0 )) s"
grep -E "Test +#|tests passed|tests failed" $OUT/ctest_bake_cuda.txt | tail -25
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
echo "total $(( $(date +%s)-t0 )) s"
