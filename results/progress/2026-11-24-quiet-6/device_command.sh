# Device call (issues 19, 16): OpenMP build of the repository root (a trial merge), the strong
# scaling runs of results/bake/run_distributed.sh on the quiet 16-core host, then (alone on the
# host) bake's progress-ETA run of results/progress (cornell_big_raw N=4000 K=6, 7200 gather rays,
# 1 thread pinned), and optional extra commands in $EXTRA.
source .carry/dev_env.sh
R=$(pwd); t0=$(date +%s)
{ echo "commit $(cat .carry/commit_trial.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
cmake -S . -B build "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-omp -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg.log 2>&1 || tail -20 $OUT/cfg.log
cmake --build build -j 16 --target bake rtmini-gen-inputs > $OUT/build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build.log | head -20
[ "${STRONG:-1}" = 1 ] && { bash results/bake/run_distributed.sh $OUT/strong strong > $OUT/strong.txt 2>&1; echo "strong rc=$? $(( $(date +%s)-t0 )) s"; cat $OUT/strong.txt | grep -v '^==' | head -60; }
mkdir -p /tmp/eta && cd /tmp/eta && export OMP_PROC_BIND=false
taskset -c 11 timeout 200 python3 $R/results/progress/cpu_clock.py bake.log $R/build/miniapps/bake/bake $R/inputs/cornell_big/cornell_big_raw.bs -n 4000 -k 6 --gather-rays 7200 --batch-size 64 -o cb.bs --threads 1 --progress > bake.stdout
echo "eta rc=$? $(( $(date +%s)-t0 )) s"; cp bake.log bake.stdout $OUT/
python3 $R/results/progress/eta_table.py bake.log | tail -4
cd $R; [ -n "${EXTRA:-}" ] && { bash -c "$EXTRA" > $OUT/extra.txt 2>&1; echo "extra rc=$?"; tail -30 $OUT/extra.txt; }
echo "total $(( $(date +%s)-t0 )) s"
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
