# Issue 19 acceptance rows with repeats (run_distributed.sh acceptance), tree of .carry/commit.txt.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; lscpu | grep -i -E 'cache|socket|numa'; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -20 $OUT/omp_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "omp build rc=$? $(( $(date +%s)-t0 )) s"
ln -sfn ../build-omp .carry/build; ln -sfn ../inputs .carry/inputs
ACC_WEAK_P="1 2 4 8 16" ACC_ROUNDS=2 BAKE=$R/build-omp/miniapps/bake/bake timeout 470 bash .carry/results/bake/run_distributed.sh $OUT/acc acceptance > $OUT/acc.txt 2>&1; echo "acceptance rc=$? $(( $(date +%s)-t0 )) s"
python3 .carry/results/bake/acceptance_table.py $OUT/acc > $OUT/acc_table.md 2>&1; cat $OUT/acc_table.md
rm -f $OUT/*/*.bs $OUT/*/*.bsb
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.md' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
echo "total $(( $(date +%s)-t0 )) s"
(cd $OUT && tar czf /tmp/acc.tgz acc && rm -rf acc && mv /tmp/acc.tgz .)
