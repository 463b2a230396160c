# Issue 19: is the 16 x 1 slowest rank the one whose heap got fewer transparent huge pages?
# 16 x 1 (default malloc, and glibc.malloc.hugetlb=1: THP advice on every mmap'd chunk),
# 16 x 1 with the rank-to-core map reversed, 1 x 16; alternated, three rounds.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; ldd --version | head -1
  for f in enabled defrag khugepaged/defrag; do echo "thp $f: $(cat /sys/kernel/mm/transparent_hugepage/$f)"; done
  grep -E "AnonHugePages|HugePages_Total|MemFree|MemAvailable" /proc/meminfo; lscpu | grep -iE "thread|core|socket|numa"
  echo "siblings: $(cat /sys/devices/system/cpu/cpu*/topology/thread_siblings_list | sort -u | tr '\n' ' ')"; } > $OUT/provenance.txt 2>&1
build_kokkos_omp; echo "kokkos rc=$? $(( $(date +%s)-t0 )) s"
[ -f .carry/kokkos-omp-install.tgz ] || tar czf $OUT/kokkos-omp-install.tgz -C $KOMP .
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
grep -m5 -i " error" $OUT/omp_build.log; tail -3 $OUT/omp_cfg.log
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
for i in $(seq 0 15); do echo "rank $i=localhost slot=$((15-i))"; done > /tmp/reversed.rf
run() {  # run NAME NP T [env/mpirun args]
  local name=$1 np=$2 t=$3; shift 3
  OMP_NUM_THREADS=$t mpirun -n $np "$@" $B /tmp/bunny_room.bs -o /tmp/t.bsb --viewpoints 300 --iterations 4 --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed"
}
for i in 1 2 3; do
  [ $(( $(date +%s)-t0 )) -lt 460 ] || break
  run plain_16x1_$i 16 1 --map-by slot:PE=1 --bind-to core
  run hugetlb_16x1_$i 16 1 --map-by slot:PE=1 --bind-to core -x GLIBC_TUNABLES=glibc.malloc.hugetlb=1
  run reversed_16x1_$i 16 1 --rankfile /tmp/reversed.rf
  run plain_1x16_$i 1 16 --map-by slot:PE=16 --bind-to core
  run hugetlb_1x16_$i 1 16 --map-by slot:PE=16 --bind-to core -x GLIBC_TUNABLES=glibc.malloc.hugetlb=1
  echo "round $i $(( $(date +%s)-t0 )) s"
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
grep -E "AnonHugePages" /proc/meminfo >> $OUT/provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
