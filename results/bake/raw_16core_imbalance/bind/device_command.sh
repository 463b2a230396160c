# Issue 19: 16 x 1 with ranks bound to cores (as every scaling run so far) against unbound
# (--bind-to none), alternated with 1 x 16; timings files kept for per-rank iteration times.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; } > $OUT/provenance.txt
omp_configure build-omp-d14 > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp-d14 -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
build-omp-d14/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
B=$R/build-omp-d14/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
run() {  # run NAME NP T [mpirun args]
  local name=$1 np=$2 t=$3; shift 3
  OMP_NUM_THREADS=$t mpirun -n $np "$@" $B /tmp/bunny_room.bs -o /tmp/t.bsb --viewpoints 300 --iterations 4 --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed"
}
for i in 1 2 3 4; do
  [ $(( $(date +%s)-t0 )) -lt 480 ] || break
  run bound_16x1_$i 16 1 --map-by slot:PE=1 --bind-to core
  run unbound_16x1_$i 16 1 --bind-to none
  run bound_1x16_$i 1 16 --map-by slot:PE=16 --bind-to core
  run unbound_1x16_$i 1 16 --bind-to none
  echo "round $i $(( $(date +%s)-t0 )) s"
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
