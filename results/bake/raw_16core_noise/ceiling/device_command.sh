# Issue 19: the host's ceiling for parallel efficiency against 1 x 1: one bake alone, then 16
# copies of the same 1 x 1 bake at once (each bound to its own core, no communication), then
# one alone again; and 1 x 16 and 16 x 1 of the same bake in the same call.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; } > $OUT/provenance.txt 2>&1
build_kokkos_omp
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
args=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4)
solo() { OMP_NUM_THREADS=1 taskset -c 0 $B "${args[@]}" -o /tmp/solo.bsb --summary $T/$1.json > $T/$1.log 2>&1 || echo "$1 failed"; }
solo solo_before
for c in $(seq 0 15); do OMP_NUM_THREADS=1 taskset -c $c $B "${args[@]}" -o /tmp/c$c.bsb --summary $T/copy_$c.json > $T/copy_$c.log 2>&1 & done; wait
echo "copies done $(( $(date +%s)-t0 )) s"
solo solo_after
for i in 1 2; do
  OMP_NUM_THREADS=16 mpirun -n 1 --map-by slot:PE=16 --bind-to core $B "${args[@]}" -o /tmp/t.bsb --summary $T/r1x16_$i.json > $T/r1x16_$i.log 2>&1
  OMP_NUM_THREADS=1 mpirun -n 16 --map-by slot:PE=1 --bind-to core $B "${args[@]}" -o /tmp/t.bsb --summary $T/r16x1_$i.json > $T/r16x1_$i.log 2>&1
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
