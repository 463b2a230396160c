# Issue 19: the strong-scaling table with --node-sharing on (final code): 1 x 1 once, then 1 x 16,
# 2 x 8, 4 x 4, 8 x 2, 16 x 1 with on and 16 x 1 off, alternated rounds; bunny_room N=300 K=4.
source .carry/dev_env.sh  # (the session kit: unpacks Kokkos 4 OpenMP and the header-only debs; not committed)
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; lscpu | grep -i -E 'cache|socket|numa'; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; df -h /dev/shm | tail -1; cat /sys/kernel/mm/transparent_hugepage/enabled /sys/kernel/mm/transparent_hugepage/shmem_enabled; } > $OUT/provenance.txt 2>&1
build_kokkos_omp
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
args=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4)
go() {  # go NAME RANKS THREADS ARGS...
  local name=$1 p=$2 t=$3; shift 3
  OMP_NUM_THREADS=$t mpirun -n $p --map-by slot:PE=$t --bind-to core $B "${args[@]}" -o /tmp/t.bsb --summary $T/$name.json --timings $T/$name.h5 "$@" > $T/$name.log 2>&1 || echo "$name failed rc=$?"
}
go r1x1_0 1 1
echo "1x1 $(( $(date +%s)-t0 )) s"
for i in 1 2 3 4; do
  go r1x16_$i 1 16
  go r2x8_on_$i 2 8 --node-sharing on
  go r4x4_on_$i 4 4 --node-sharing on
  go r8x2_on_$i 8 2 --node-sharing on
  go r16x1_on_$i 16 1 --node-sharing on
  go r16x1_off_$i 16 1
  echo "round $i $(( $(date +%s)-t0 )) s"
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
