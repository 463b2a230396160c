# Mid-session call 2 (issue 19): OpenMP build of bake on the trial, strong scaling in one run
# (run_distributed.sh scaling) on the 16-core host.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
omp_configure build > $OUT/cfg.log 2>&1 || tail -20 $OUT/cfg.log
cmake --build build -j 16 --target bake rtmini-gen-inputs > $OUT/build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build.log | head -20
timeout ${LIMIT:-300} bash results/bake/run_distributed.sh $OUT/scaling scaling > $OUT/scaling.txt 2>&1; echo "scaling rc=$? $(( $(date +%s)-t0 )) s"
grep -v '^==' $OUT/scaling.txt | tail -30
rm -f $OUT/*/*.bs $OUT/*/*.bsb
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
echo "total $(( $(date +%s)-t0 )) s"
