# Mid-session device call B (warm, after dev_mid5_a.sh): unit ctests on CUDA; the builders (main
# bench against the trial's); while those run, sketchtrace built with RTMINI_SKETCH_MIN_BLOCKS=3
# and 4 in the background (sketchtrace only).
source .carry/dev_env.sh
t0=$(date +%s)
[ -x build-cuda/bench/rtmini-bvh-bench ] || { echo "no build-cuda: the machine was not warm"; exit 1; }
for mb in 3 4; do (cmake -S . -B build-mb$mb "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF -DRTMINI_SKETCH_MIN_BLOCKS=$mb > $OUT/cfg_mb$mb.log 2>&1 &&
  nice cmake --build build-mb$mb -j 5 --target sketchtrace > $OUT/build_mb$mb.log 2>&1; echo "mb$mb build rc=$? $(( $(date +%s)-t0 )) s") & done
(cd build-cuda && timeout 200 ctest -R "unit.core.cuda|unit.ao|unit.sketchtrace" --timeout 190 -j 4 > $OUT/unit_cuda.txt 2>&1; echo "ctest rc=$? $(( $(date +%s)-t0 )) s"; grep -E "tests passed|\(Failed\)|Not Run|Timeout" $OUT/unit_cuda.txt | head -20)
NB=build-cuda/bench/rtmini-bvh-bench MB=/tmp/s_main/b/bench/rtmini-bvh-bench
for m in stanford-bunny dragon; do for q in ploc; do for b in main:$MB trial:$NB; do
  timeout 60 ${b#*:} inputs/meshes/$m.obj --workload ao --quality $q --repeats 3 --time-builds lbvh,ploc,sah > $OUT/builds_${m}_${b%%:*}.log 2>&1
  echo "$m ${b%%:*}: $(grep -E 'build|SAH cost|Grays|verification' $OUT/builds_${m}_${b%%:*}.log | tr -s ' ' | tr '\n' '|' | cut -c1-600)"; done; done; done
for c in 10 100; do for b in main:$MB trial:$NB; do
  timeout 90 ${b#*:} inputs/meshes/dragon.obj --copies $c --quality lbvh --build-phases --repeats 10 --samples-per-face 1 --rays 1 --time-builds lbvh,ploc > $OUT/lbvh_x${c}_${b%%:*}.log 2>&1
  echo "dragon x$c ${b%%:*}: $(grep -E 'lbvh|LBVH|phase|build' $OUT/lbvh_x${c}_${b%%:*}.log | tr -s ' ' | tr '\n' '|' | cut -c1-500)"; done; done
wait
echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
