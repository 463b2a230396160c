# Device call (issue 21): CUDA builds of the repository root (a trial merge of the session's
# branches) and of main 222749d (the session's baseline, .carry/base_222749d.tgz), unit.core.cuda,
# then the bench: AO any-hit kernels x ray orders (branch gputrav), LBVH/PLOC build phases and
# SAH cost (gpubuild), and the AO whole bake of dragon x4 (aobake), baseline and trial alternated.
source .carry/dev_env.sh
R=$(pwd); t0=$(date +%s)
{ echo "trial commit $(cat .carry/commit_trial.txt)"; echo "baseline main 222749d"; date -u
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
mkdir -p /tmp/base && tar -xzf .carry/base_222749d.tgz -C /tmp/base && ln -sfn $R/inputs/meshes /tmp/base/inputs/meshes
cfg() { cmake -S $1 -B $2 "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ $3 > $OUT/cfg_$4.log 2>&1 || tail -20 $OUT/cfg_$4.log; }
[ "${BASE:-1}" = 1 ] && (cfg /tmp/base /tmp/base/build -DRTMINI_ENABLE_TESTS=OFF base && cmake --build /tmp/base/build -j 6 --target rtmini-bvh-bench bake > $OUT/build_base.log 2>&1; echo "base build rc=$? $(( $(date +%s)-t0 )) s") &
(cfg . build-cuda "" new && cmake --build build-cuda -j 10 --target rtmini-bvh-bench bake rtmini_unit_core_cuda > $OUT/build_new.log 2>&1; echo "new build rc=$? $(( $(date +%s)-t0 )) s") &
wait
grep -h -E ' error' -A3 $OUT/build_base.log $OUT/build_new.log | head -30
[ "${SKIPUNIT:-0}" = 1 ] || (cd build-cuda && timeout 200 ctest -R unit.core.cuda --timeout 190 --output-on-failure > $OUT/unit_core_cuda.txt 2>&1; echo "unit.core.cuda rc=$? $(( $(date +%s)-t0 )) s"; grep -E 'tests passed|^\[  FAILED|^\[  PASSED' $OUT/unit_core_cuda.txt | head)
NB=build-cuda/bench/rtmini-bvh-bench OB=/tmp/base/build/bench/rtmini-bvh-bench
L=$OUT/bench.txt
b() { local tag=$1; shift; [ -x "$1" ] || return 0; echo "== $tag ${*:2}" >> $L; timeout 60 "$@" >> $L 2>&1; echo "rc=$?" >> $L; }
for m in dragon stanford-bunny; do for q in sah lbvh; do
  b base $OB inputs/meshes/$m.obj --workload ao --quality $q
  for k in ${KERNELS:-default wide stored short8 short16}; do
    b new $NB inputs/meshes/$m.obj --workload ao --quality $q --gpu-trace $k
  done
  [ $q = sah ] && b new $NB inputs/meshes/$m.obj --workload ao --quality $q --gpu-trace default --ray-order coherent
done; done
echo "kernels done $(( $(date +%s)-t0 )) s"
for rep in 1 2 3; do for t in base new new1; do
  bin=/tmp/base/build/miniapps/bake/bake; [ $t != base ] && bin=build-cuda/miniapps/bake/bake
  [ -x $bin ] || continue
  [ $t = new1 ] && export RTMINI_OBJ_THREADS=1 || unset RTMINI_OBJ_THREADS
  timeout 60 $bin ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/ao_$t.glb --summary $OUT/ao_${t}_$rep.json > $OUT/ao_${t}_$rep.log 2>&1
  echo "ao $t $rep rc=$? $(grep -E 'Whole bake|verification' $OUT/ao_${t}_$rep.log | tr '\n' ' ' | cut -c1-200)"
done; done
cmp /tmp/ao_new1.glb /tmp/ao_new.glb && echo "ao glb identical (1 and 16 OBJ threads)"; [ -f /tmp/ao_base.glb ] && cmp /tmp/ao_base.glb /tmp/ao_new.glb && echo "ao glb identical to the baseline"
for m in "inputs/meshes/dragon.obj" "inputs/meshes/stanford-bunny.obj" "icosphere:8" "inputs/meshes/dragon.obj --copies 10" "inputs/meshes/dragon.obj --copies 100"; do
  b base $OB $m --workload ao --quality lbvh --rays 4 --samples-per-face 1
  b new $NB $m --workload ao --quality lbvh --rays 4 --samples-per-face 1 --time-builds lbvh,ploc --build-phases
  b new $NB $m --workload ao --quality ploc --rays 4 --samples-per-face 1
done
b new $NB inputs/meshes/dragon.obj --workload ao --quality lbvh --rays 4 --samples-per-face 1 --time-builds lbvh,ploc,sah
b new $NB inputs/meshes/stanford-bunny.obj --workload ao --quality lbvh --rays 4 --samples-per-face 1 --time-builds lbvh,ploc,sah
echo "builds done $(( $(date +%s)-t0 )) s"
grep -E '^== |Grays|Mrays|FOM|build|SAH cost|verification|hit fraction' $L | cut -c1-200 > $OUT/bench_summary.txt
echo "total $(( $(date +%s)-t0 )) s"
# The device tool brings back a few files only: everything in one archive.
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
