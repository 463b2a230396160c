# Device call (issue 19): OpenMP build of the repository root (a trial merge), then the strong and
# weak scaling runs of results/bake/run_distributed.sh on the 16-core host.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit_trial.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
cmake -S . -B build "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-omp -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg.log 2>&1 || tail -20 $OUT/cfg.log
cmake --build build -j 16 --target bake rtmini-gen-inputs > $OUT/build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build.log | head -20
for w in ${WHAT:-strong weak}; do
  timeout ${LIMIT:-250} bash results/bake/run_distributed.sh $OUT/$w $w > $OUT/$w.txt 2>&1; echo "$w rc=$? $(( $(date +%s)-t0 )) s"
  grep -v '^==' $OUT/$w.txt | head -40
done
rm -f $OUT/*/*.bs $OUT/*/*.bsb
echo "total $(( $(date +%s)-t0 )) s"
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
