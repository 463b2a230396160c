# Final device call B (warm, after dev_fin6_a.sh): finish the build; core unit ctests on CUDA; the
# LBVH build (main's bench against the trial's, alternated); AO bench hashes.
source .carry/dev_env.sh
t0=$(date +%s)
[ -d build-cuda ] || { echo "no build-cuda: the machine was not warm"; exit 1; }
cmake --build build-cuda -j 16 --target rtmini-bvh-bench rtmini_unit_core_cuda -- -k 0 > $OUT/build_cuda_b.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
(cd build-cuda && timeout 280 ctest -R "unit.core.cuda" --timeout 270 > $OUT/unit_core_cuda.txt 2>&1; echo "ctest rc=$? $(( $(date +%s)-t0 )) s"; grep -E "tests passed|\(Failed\)|Not Run|Timeout" $OUT/unit_core_cuda.txt | head -20)
NB=build-cuda/bench/rtmini-bvh-bench MB=/tmp/s_main/b/bench/rtmini-bvh-bench
for rep in 1 2 3; do for c in 10 100; do for b in main:$MB trial:$NB; do
  timeout 40 ${b#*:} inputs/meshes/dragon.obj --copies $c --quality lbvh --build-phases --repeats 5 --samples-per-face 1 --rays 1 --time-builds lbvh > $OUT/lbvh_x${c}_${b%%:*}_$rep.log 2>&1
  echo "x$c ${b%%:*} $rep: $(grep -E '^build:|lbvh phases|verification' $OUT/lbvh_x${c}_${b%%:*}_$rep.log | cut -c1-150 | tr '\n' '|')"; done; done; done
for m in dragon stanford-bunny; do for q in sah lbvh; do timeout 60 $NB inputs/meshes/$m.obj --workload ao --quality $q > $OUT/bench_${m}_$q.log 2>&1; echo "bench $m $q: $(grep -E 'per ray|FOM' $OUT/bench_${m}_$q.log | tr '\n' '|')"; done; done
echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
