# Weak scaling on closed rooms with and without --node-sharing on (issue 19), tree of .carry/commit.txt.
source .carry/dev_env.sh  # (the session kit: unpacks Kokkos 4 OpenMP and the header-only debs; not committed)
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
build_kokkos_omp
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -20 $OUT/omp_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "omp build rc=$? $(( $(date +%s)-t0 )) s"
echo "load after build $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
BAKE=$R/build-omp/miniapps/bake/bake timeout 420 bash results/bake/run_distributed.sh $OUT/weak weakshare > $OUT/weak.txt 2>&1; echo "weakshare rc=$? $(( $(date +%s)-t0 )) s"
tail -40 $OUT/weak/table.md 2>/dev/null
rm -f $OUT/*/*.bs $OUT/*/*.bsb
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.md' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
echo "total $(( $(date +%s)-t0 )) s"
