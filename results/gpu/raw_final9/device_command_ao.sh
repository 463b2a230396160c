# Call 1 (session of 2026-11-25, 03:25-): CUDA build of the tree of .carry/commit.txt (bench + core
# unit tests), unit.core.cuda; then main's bench (.carry/base-src.tgz) and AO on both, alternated.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt), base $(cat .carry/base_commit.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
kokkos_cuda
cuda_configure build-cuda > $OUT/cfg.log 2>&1 || tail -30 $OUT/cfg.log
cmake --build build-cuda -j 16 --target rtmini-bvh-bench rtmini_unit_core_cuda > $OUT/build.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build.log | head -20
mkdir -p /tmp/base-src && tar xzf .carry/base-src.tgz -C /tmp/base-src
( cd /tmp/base-src && cp -r $R/.carry . && cuda_configure $R/build-base > $OUT/base_cfg.log 2>&1 && cmake --build $R/build-base -j 12 --target rtmini-bvh-bench > $OUT/base_build.log 2>&1; echo "base build rc=$?" >> $OUT/base_build.log ) &
(cd build-cuda && timeout 200 ctest -R 'unit.core.cuda' --output-on-failure --timeout 190 > $OUT/unit_core_cuda.txt 2>&1); echo "unit.core.cuda rc=$? $(( $(date +%s)-t0 )) s"
tail -3 $OUT/unit_core_cuda.txt
wait; tail -1 $OUT/base_build.log; echo "base built $(( $(date +%s)-t0 )) s"
for round in 1 2; do for b in build-cuda build-base; do for q in sah lbvh; do for m in dragon stanford-bunny; do
  [ -x $b/bench/rtmini-bvh-bench ] || continue
  timeout 40 $b/bench/rtmini-bvh-bench inputs/meshes/$m.obj --workload ao --quality $q > $OUT/ao_${b}_${m}_${q}_$round.txt 2>&1
  echo "$round $b $m $q: $(grep '^FOM' $OUT/ao_${b}_${m}_${q}_$round.txt | head -1) $(grep -o 'verification [0-9a-f]*' $OUT/ao_${b}_${m}_${q}_$round.txt | head -1)"; done; done; done; done
echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/base-src|BASE_SRC|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
