# Device call (issue 21, LBVH build): CUDA builds of rtmini-bvh-bench only, for main
# (.carry/src_main.tgz), branch lbvh6 alone (.carry/src_lbvh6.tgz) and the repository root (lbvh6
# with bakeweak6's extent-shared Morton codes merged); then the LBVH build at 1M and 10M
# triangles (dragon x10, x100) alternated over the three, 3 rounds; then AO any hit on the LBVH
# trees (x10, x100) for each, twice.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "root $(cat .carry/commit_trial.txt) lbvh6 $(cat .carry/commit_lbvh6.txt) main $(cat .carry/commit_main.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
bench_of() {  # bench_of NAME TGZ: unpack and build rtmini-bvh-bench in /tmp/s_NAME/b
  mkdir -p /tmp/s_$1 && tar -xzf $2 -C /tmp/s_$1 && rm -rf /tmp/s_$1/inputs/meshes && ln -sfn $PWD/inputs/meshes /tmp/s_$1/inputs/meshes && cd /tmp/s_$1 &&
  cmake -S . -B b "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_$1.log 2>&1 &&
  cmake --build b -j 5 --target rtmini-bvh-bench -- -k 0 > $OUT/build_$1.log 2>&1; echo "$1 bench build rc=$? $(( $(date +%s)-t0 )) s"
  grep -E ' error' -A3 $OUT/build_$1.log | head -20
}
bench_of main .carry/src_main.tgz &
bench_of lbvh6 .carry/src_lbvh6.tgz &
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
cmake --build build-cuda -j 6 --target rtmini-bvh-bench -- -k 0 > $OUT/build_cuda.log 2>&1; echo "root bench build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build_cuda.log | head -30
wait
B="main:/tmp/s_main/b/bench/rtmini-bvh-bench lbvh6:/tmp/s_lbvh6/b/bench/rtmini-bvh-bench root:build-cuda/bench/rtmini-bvh-bench"
for rep in 1 2 3; do for c in 10 100; do for b in $B; do
  timeout 40 ${b#*:} inputs/meshes/dragon.obj --copies $c --quality lbvh --build-phases --repeats 5 --samples-per-face 1 --rays 1 --time-builds lbvh > $OUT/lbvh_x${c}_${b%%:*}_$rep.log 2>&1
  echo "x$c ${b%%:*} $rep: $(grep -E '^build:|lbvh phases|verification' $OUT/lbvh_x${c}_${b%%:*}_$rep.log | cut -c1-150 | tr '\n' '|')"; done; done; done
for rc in 1:10 2:10 1:100; do rep=${rc%:*} c=${rc#*:}; for b in $B; do
  timeout 60 ${b#*:} inputs/meshes/dragon.obj --copies $c --quality lbvh --workload ao --repeats 2 > $OUT/ao_x${c}_${b%%:*}_$rep.log 2>&1
  echo "ao x$c ${b%%:*} $rep: $(grep -E 'per ray|FOM' $OUT/ao_x${c}_${b%%:*}_$rep.log | cut -c1-150 | tr '\n' '|')"; done; done
echo "total $(( $(date +%s)-t0 )) s"
find $OUT -name '*.log' -o -name '*.txt' | xargs sed -i "s|$(pwd)|.|g; s|OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
