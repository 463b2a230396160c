# Final device call B (warm, after dev_fin5_a.sh): finish the build; unit ctests on CUDA; the
# builders (main's bench against the trial's, alternated); sketchtrace; the AO whole bake; AO bench.
source .carry/dev_env.sh
t0=$(date +%s)
[ -d build-cuda ] || { echo "no build-cuda: the machine was not warm"; exit 1; }
cmake --build build-cuda -j 16 --target sketchtrace rtmini-bvh-bench bake rtmini_unit_core_cuda rtmini_unit_ao rtmini_unit_sketchtrace rtmini_unit_bake -- -k 0 > $OUT/build_cuda_b.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
(cd build-cuda && timeout 200 ctest -R "unit.core.cuda|unit.ao|unit.sketchtrace|unit.bake" --timeout 190 -j 4 > $OUT/unit_cuda.txt 2>&1; echo "ctest rc=$? $(( $(date +%s)-t0 )) s"; grep -E "tests passed|\(Failed\)|Not Run|Timeout" $OUT/unit_cuda.txt | head -20)
NB=build-cuda/bench/rtmini-bvh-bench MB=/tmp/s_main/b/bench/rtmini-bvh-bench
for rep in 1 2; do for c in 10 100; do for b in main:$MB trial:$NB; do
  timeout 40 ${b#*:} inputs/meshes/dragon.obj --copies $c --quality lbvh --build-phases --repeats 5 --samples-per-face 1 --rays 1 --time-builds lbvh > $OUT/lbvh_x${c}_${b%%:*}_$rep.log 2>&1
  echo "x$c ${b%%:*} $rep: $(grep -E '^build:|lbvh phases' $OUT/lbvh_x${c}_${b%%:*}_$rep.log | cut -c1-140 | tr '\n' '|')"; done; done; done
for m in dragon stanford-bunny; do for b in main:$MB trial:$NB; do
  timeout 60 ${b#*:} inputs/meshes/$m.obj --workload ao --quality ploc --repeats 3 --time-builds lbvh,ploc,sah > $OUT/builds_${m}_${b%%:*}.log 2>&1
  echo "$m ${b%%:*}: $(grep -E '^build:|sah cost|FOM' $OUT/builds_${m}_${b%%:*}.log | cut -c1-160 | tr '\n' '|')"; done; done
mkdir -p $OUT/sketch
OUT=$OUT/sketch timeout 150 bash results/gpu/sketchtrace_device.sh trial=build-cuda > $OUT/sketch.txt 2>&1; echo "sketch rc=$? $(( $(date +%s)-t0 )) s"; grep -v "^ " $OUT/sketch.txt | tail -12
for rep in 1 2 3; do timeout 60 build-cuda/miniapps/bake/bake ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/d.glb > $OUT/ao_rep$rep.log 2>&1; echo "ao rep$rep rc=$? $(grep -E 'upload receivers|Whole bake|verification' $OUT/ao_rep$rep.log | tr -s ' ' | tr '\n' '|')"; done
for m in dragon stanford-bunny; do timeout 60 $NB inputs/meshes/$m.obj --workload ao --quality sah > $OUT/bench_$m.log 2>&1; echo "bench $m: $(grep -E 'FOM' $OUT/bench_$m.log | tr '\n' '|')"; done
echo "total $(( $(date +%s)-t0 )) s"
rm -f $OUT/sketch/*.png $OUT/sketch/*.ppm
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
