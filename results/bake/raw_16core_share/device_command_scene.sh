# Issue 19: one copy of the scene per node (--node-sharing scene|on) against work sharing alone
# and no sharing, bunny_room N=300 K=4, 16-core host, alternated rounds. Never committed as is:
# dev_env.sh unpacks the fetched Kokkos.
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
for i in 1 2 3 4 5; do
  go r1x16_$i 1 16
  go r16x1_off_$i 16 1
  go r16x1_scene_$i 16 1 --node-sharing scene
  go r16x1_work_$i 16 1 --node-sharing work
  go r16x1_on_$i 16 1 --node-sharing on
  go r8x2_work_$i 8 2 --node-sharing work
  go r8x2_on_$i 8 2 --node-sharing on
  echo "round $i $(( $(date +%s)-t0 )) s"
done
args=(/tmp/bunny_room.bs --viewpoints 300 --iterations 8)
for i in 1 2; do go k8_1x16_$i 1 16; go k8_16x1_work_$i 16 1 --node-sharing work; go k8_16x1_on_$i 16 1 --node-sharing on; done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
