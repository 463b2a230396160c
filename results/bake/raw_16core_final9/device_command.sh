# Call 3 (issue 19): OpenMP builds of bake for the trial (build-omp-trial/) and for main
# (build-omp-main/, from .carry/base-src.tgz), then run_distributed.sh scaling alternated:
# main, trial, main again if time is left.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "trial $(cat .carry/commit.txt), main $(cat .carry/base_commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
rm -rf /tmp/base-src build-omp-trial build-omp-main; mkdir -p /tmp/base-src && tar xzf .carry/base-src.tgz -C /tmp/base-src
omp_configure build-omp-trial > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp-trial -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "trial build rc=$? $(( $(date +%s)-t0 )) s"
( cd /tmp/base-src && cp -r $R/.carry . && omp_configure $R/build-omp-main > $OUT/base_cfg.log 2>&1 && cmake --build $R/build-omp-main -j 16 --target bake > $OUT/base_build.log 2>&1 ); echo "main build rc=$? $(( $(date +%s)-t0 )) s"
grep -h "Kokkos_DIR\|Kokkos_ROOT" build-omp-trial/CMakeCache.txt build-omp-main/CMakeCache.txt | head -4 >> $OUT/provenance.txt
mkdir -p build/inputs && ln -sf $R/build-omp-trial/inputs/rtmini-gen-inputs build/inputs/rtmini-gen-inputs
echo "load after builds $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
for run in main:build-omp-main trial:build-omp-trial main2:build-omp-main; do
  [ $(( $(date +%s)-t0 )) -lt 430 ] || break
  BAKE=$R/${run#*:}/miniapps/bake/bake timeout 160 bash results/bake/run_distributed.sh $OUT/${run%%:*} scaling > $OUT/${run%%:*}.txt 2>&1; echo "${run%%:*} rc=$? $(( $(date +%s)-t0 )) s"
done
for f in main trial main2; do [ -f $OUT/$f/table.md ] && { echo "== $f"; grep -A9 'Strong scaling in one run' $OUT/$f/table.md | tail -7; }; done
rm -f $OUT/*/*.bs $OUT/*/*.bsb
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.md' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/base-src|BASE_SRC|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
echo "total $(( $(date +%s)-t0 )) s"
