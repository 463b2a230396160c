# Device call (issue 21): the LBVH build of main at the session end against main f9b76d3 (.carry/src_main.tgz), both CUDA builds of rtmini-bvh-bench, dragon x10 (1.0M) and x100 (10M), alternated, 3 rounds.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "root $(cat .carry/commit_trial.txt) main $(cat .carry/commit_main.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
bench_of() {  # bench_of NAME TGZ: unpack and build rtmini-bvh-bench in /tmp/s_NAME/b
  mkdir -p /tmp/s_$1 && tar -xzf $2 -C /tmp/s_$1 && rm -rf /tmp/s_$1/inputs/meshes && ln -sfn $PWD/inputs/meshes /tmp/s_$1/inputs/meshes && cd /tmp/s_$1 &&
  cmake -S . -B b "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_$1.log 2>&1 &&
  cmake --build b -j 5 --target rtmini-bvh-bench -- -k 0 > $OUT/build_$1.log 2>&1; echo "$1 bench build rc=$? $(( $(date +%s)-t0 )) s"
  grep -E ' error' -A3 $OUT/build_$1.log | head -20
}
bench_of main .carry/src_main.tgz &

cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
cmake --build build-cuda -j 10 --target rtmini-bvh-bench -- -k 0 > $OUT/build_cuda.log 2>&1; echo "root bench build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build_cuda.log | head -30
wait
B="main:/tmp/s_main/b/bench/rtmini-bvh-bench root:build-cuda/bench/rtmini-bvh-bench"
for rep in 1 2 3; do for c in 10 100; do for b in $B; do
  timeout 40 ${b#*:} inputs/meshes/dragon.obj --copies $c --quality lbvh --build-phases --repeats 5 --samples-per-face 1 --rays 1 --time-builds lbvh > $OUT/lbvh_x${c}_${b%%:*}_$rep.log 2>&1
  echo "x$c ${b%%:*} $rep: $(grep -E '^build:|lbvh phases|verification' $OUT/lbvh_x${c}_${b%%:*}_$rep.log | cut -c1-150 | tr '\n' '|')"; done; done; done
echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
