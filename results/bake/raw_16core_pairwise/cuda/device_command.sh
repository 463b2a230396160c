# Issue 19: the bake checks on CUDA after the pairwise exchanges (branch bake14).
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
cuda_configure build-cuda14 > $OUT/cfg.log 2>&1 || tail -30 $OUT/cfg.log
cmake --build build-cuda14 -j 16 --target bake rtmini-gen-inputs rtmini_unit_bake rtmini_unit_bsb > $OUT/build.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
(cd build-cuda14 && ctest -N -R 'bake.reference' | tail -1; timeout 400 ctest -R 'unit.bake$|bake.distributed|bake.decomposition|bake.restart.np|bake.hemisphere|bake.binary_output|bake.furnace|bake.reference' --output-on-failure --timeout 120 > $OUT/ctest_bake_cuda.txt 2>&1); echo "ctest rc=$? $(( $(date +%s)-t0 )) s"
grep -E "Test +#|tests passed|tests failed|device backend" $OUT/ctest_bake_cuda.txt | tail -25
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
