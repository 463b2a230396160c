# Issue 19: 16 x 1 and 8 x 2 with the counted cut (--balance cost, the default) against the measured
# recut after iteration 1 (--balance measured), alternated with 1 x 16; timings files kept.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; } > $OUT/provenance.txt
omp_configure build-omp-e14 > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp-e14 -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
build-omp-e14/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
B=$R/build-omp-e14/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
run() {  # run NAME NP T [mpirun args]
  local name=$1 np=$2 t=$3; shift 3
  local margs=() bargs=(); while [ $# -gt 0 ] && [ "$1" != -- ]; do margs+=("$1"); shift; done; [ $# -gt 0 ] && shift; bargs=("$@")
  OMP_NUM_THREADS=$t mpirun -n $np "${margs[@]}" $B "${bargs[@]}" /tmp/bunny_room.bs -o /tmp/t.bsb --viewpoints 300 --iterations 4 --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed"
}
for i in 1 2 3 4; do
  [ $(( $(date +%s)-t0 )) -lt 480 ] || break
  run cost_16x1_$i 16 1 --map-by slot:PE=1 --bind-to core
  run measured_16x1_$i 16 1 --map-by slot:PE=1 --bind-to core -- --balance measured
  run cost_8x2_$i 8 2 --map-by slot:PE=2 --bind-to core
  run measured_8x2_$i 8 2 --map-by slot:PE=2 --bind-to core -- --balance measured
  run cost_1x16_$i 1 16 --map-by slot:PE=16 --bind-to core
  echo "round $i $(( $(date +%s)-t0 )) s"
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
