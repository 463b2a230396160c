# Call 2 (issue 19): OpenMP builds of bake for the trial (build/) and for main (build-base/, from
# .carry/base-src.tgz), then strong scaling in one call through run_distributed.sh scaling:
# main, trial, trial again if time is left.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit.txt), main $(cat .carry/base_commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
mkdir -p /tmp/base-src && tar xzf .carry/base-src.tgz -C /tmp/base-src
omp_configure build > $OUT/omp_cfg.log 2>&1 && cmake --build build -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "trial build rc=$? $(( $(date +%s)-t0 )) s"
( cd /tmp/base-src && cp -r $R/.carry . && omp_configure $R/build-base > $OUT/base_cfg.log 2>&1 && cmake --build $R/build-base -j 16 --target bake > $OUT/base_build.log 2>&1 ); echo "main build rc=$? $(( $(date +%s)-t0 )) s"
echo "load after builds $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
BAKE=$R/build-base/miniapps/bake/bake timeout 170 bash results/bake/run_distributed.sh $OUT/main scaling > $OUT/main.txt 2>&1; echo "main rc=$? $(( $(date +%s)-t0 )) s"
timeout 170 bash results/bake/run_distributed.sh $OUT/trial scaling > $OUT/trial.txt 2>&1; echo "trial rc=$? $(( $(date +%s)-t0 )) s"
[ $(( $(date +%s)-t0 )) -lt 400 ] && { timeout 170 bash results/bake/run_distributed.sh $OUT/trial2 scaling > $OUT/trial2.txt 2>&1; echo "trial2 rc=$? $(( $(date +%s)-t0 )) s"; }
for f in main trial trial2; do [ -f $OUT/$f/table.md ] && { echo "== $f"; grep -A9 'Strong scaling in one run' $OUT/$f/table.md | tail -7; }; done
[ -f results/bake/raw_memory10/resident.py ] && python3 results/bake/raw_memory10/resident.py $OUT/trial/scaling_16x1_1.json > $OUT/trial_resident_16x1.txt 2>&1; head -20 $OUT/trial_resident_16x1.txt
rm -f $OUT/*/*.bs $OUT/*/*.bsb
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.md' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/base-src|BASE_SRC|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
echo "total $(( $(date +%s)-t0 )) s"
