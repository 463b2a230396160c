# Device call B (warm machine after dev_fin3_a.sh): the unit ctests on CUDA, sketchtrace main
# against the trial (and the two dist_first images compared), the AO whole bake, the AO bench.
source .carry/dev_env.sh
t0=$(date +%s)
[ -d build-cuda ] || { echo "no build-cuda: the machine was not warm"; exit 1; }
cmake --build build-cuda -j 16 -- -k 0 > $OUT/build_cuda_b.log 2>&1; echo "cuda build (incremental) rc=$? $(( $(date +%s)-t0 )) s"
(cd build-cuda && timeout 300 ctest -L unit --timeout 280 -j 8 > $OUT/unit_cuda.txt 2>&1; echo "ctest rc=$? $(( $(date +%s)-t0 )) s"; grep -E "tests passed|\(Failed\)|Not Run|Timeout" $OUT/unit_cuda.txt | head -20)
mkdir -p $OUT/sketch
OUT=$OUT/sketch timeout 170 bash results/gpu/sketchtrace_device.sh main=/tmp/s_main/b trial=build-cuda > $OUT/sketch.txt 2>&1; echo "sketch rc=$? $(( $(date +%s)-t0 )) s"; grep -v "^ " $OUT/sketch.txt | tail -22
S=build-cuda/miniapps/sketchtrace/sketchtrace; A=build-cuda/tests/regression/stability/rtmini-image-agreement
for b in main:/tmp/s_main/b/miniapps/sketchtrace/sketchtrace trial:$S; do timeout 30 ${b#*:} inputs/dist_first/dist_first.toml --width 1000 --height 800 --spp 32 -o /tmp/dist_${b%%:*}.ppm > $OUT/dist_ppm_${b%%:*}.log 2>&1; done
[ -x $A ] && { echo "dist_first trial vs main image: $($A /tmp/dist_trial.ppm /tmp/dist_main.ppm 2>&1 | tail -2 | tr '\n' ' ')"; cmp -s /tmp/dist_trial.ppm /tmp/dist_main.ppm && echo "dist_first images byte-identical"; }
B=build-cuda/miniapps/bake/bake; NB=build-cuda/bench/rtmini-bvh-bench
for rep in 1 2 3; do timeout 60 $B ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/d.glb > $OUT/ao_rep$rep.log 2>&1; echo "ao rep$rep rc=$? $(grep -E 'Whole bake|verification' $OUT/ao_rep$rep.log | tr -s ' ' | tr '\n' '|')"; done
for m in dragon stanford-bunny; do for k in default speculative; do timeout 60 $NB inputs/meshes/$m.obj --workload ao --quality sah --gpu-trace $k > $OUT/bench_${m}_$k.log 2>&1; echo "bench $m $k: $(grep -E 'Grays|Mrays|verification' $OUT/bench_${m}_$k.log | tail -2 | tr -s ' ' | tr '\n' '|')"; done; done
echo "total $(( $(date +%s)-t0 )) s"
rm -f $OUT/sketch/*.png
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
