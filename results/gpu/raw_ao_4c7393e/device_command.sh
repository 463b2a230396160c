# Device call (issue 21): where the AO whole bake's host-side time goes, and PLOC's trace rate for --bvh auto.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit_trial.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; which nsys ncu; } > $OUT/provenance.txt 2>&1
build_rtmini cuda -DRTMINI_ENABLE_TESTS=OFF > $OUT/build.txt 2>&1 || true
cmake --build build-cuda -j 16 --target bake rtmini-bvh-bench >> $OUT/build.txt 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
B=build-cuda/miniapps/bake/bake NB=build-cuda/bench/rtmini-bvh-bench
for rep in 1 2 3; do for mode in lazy eager; do
  [ $mode = eager ] && export CUDA_MODULE_LOADING=EAGER || unset CUDA_MODULE_LOADING
  /usr/bin/time -f "process wall %e s, maxrss %M KB" timeout 60 $B ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/ao.glb > $OUT/ao_${mode}_$rep.log 2>&1
  echo "ao $mode $rep rc=$? $(grep -E 'Build BVHs|mesh BVHs|upload rec|Whole bake|process wall' $OUT/ao_${mode}_$rep.log | tr -s ' ' | tr '\n' '|')"
done; done
unset CUDA_MODULE_LOADING
L=$OUT/bench.txt
for m in dragon stanford-bunny; do for q in ploc lbvh sah; do
  echo "== $m $q" >> $L; timeout 90 $NB inputs/meshes/$m.obj --workload ao --quality $q >> $L 2>&1; echo "rc=$?" >> $L
done; done
grep -E '^== |Mrays/s|per ray|build:' $L | cut -c1-180
if which nsys >/dev/null 2>&1; then
  timeout 120 nsys profile -o /tmp/ao_prof --stats=false $B ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/ao.glb > $OUT/nsys_run.log 2>&1
  timeout 120 nsys stats --report cuda_api_sum,cuda_gpu_kern_sum,cuda_gpu_mem_time_sum /tmp/ao_prof.nsys-rep > $OUT/nsys_stats.txt 2>&1
  head -60 $OUT/nsys_stats.txt
fi
echo "total $(( $(date +%s)-t0 )) s"
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
