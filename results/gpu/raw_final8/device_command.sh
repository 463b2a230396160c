# Final call 1 (session of 2026-11-25): CUDA build of the trial (bench + core unit tests),
# unit.core.cuda, AO hashes on dragon/bunny (SAH, LBVH); in the background the OpenMP bake builds
# of the trial (build/) and of main (build-main/, from .carry/main-src.tgz) for call 2.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
kokkos_omp; kokkos_cuda
mkdir -p /tmp/main-src && tar xzf .carry/main-src.tgz -C /tmp/main-src
( omp_configure build > $OUT/omp_cfg.log 2>&1 && cmake --build build -j 5 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "omp build rc=$?" >> $OUT/omp_build.log
  cd /tmp/main-src && cp -r $R/.carry . && omp_configure $R/build-main > $OUT/main_cfg.log 2>&1 && cmake --build $R/build-main -j 5 --target bake > $OUT/main_build.log 2>&1; echo "main build rc=$?" >> $OUT/main_build.log ) &
cuda_configure build-cuda > $OUT/cfg.log 2>&1 || tail -30 $OUT/cfg.log
cmake --build build-cuda -j 11 --target rtmini-bvh-bench rtmini_unit_core_cuda > $OUT/build.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build.log | head -20
(cd build-cuda && timeout 300 ctest -R 'unit.core.cuda' --output-on-failure --timeout 290 > $OUT/unit_core_cuda.txt 2>&1); echo "unit.core.cuda rc=$? $(( $(date +%s)-t0 )) s"
tail -4 $OUT/unit_core_cuda.txt
for q in sah lbvh; do for m in dragon stanford-bunny; do
  timeout 60 build-cuda/bench/rtmini-bvh-bench inputs/meshes/$m.obj --workload ao --quality $q > $OUT/ao_${m}_$q.txt 2>&1
  echo "$m $q: $(grep '^FOM' $OUT/ao_${m}_$q.txt)"; done; done
wait; tail -1 $OUT/omp_build.log; tail -1 $OUT/main_build.log; echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/main-src|MAIN_SRC|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
