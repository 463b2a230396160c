# Issue 19: does a rank's slowness follow its process or its core within one run? 16 x 1,
# K = 6; in "rotate" runs every rank's process is moved from core r to core (r + 8) % 16 about
# 3.2 s after launch (during iteration 3), by taskset on each rank's pid; "still" runs are left.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; } > $OUT/provenance.txt 2>&1
build_kokkos_omp
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
run16() {  # run16 NAME still|rotate
  local name=$1
  OMP_NUM_THREADS=1 mpirun -n 16 --map-by slot:PE=1 --bind-to core $B /tmp/bunny_room.bs -o /tmp/t.bsb --viewpoints 300 --iterations 6 --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 &
  local mp=$!
  if [ "$2" = rotate ]; then
    sleep 3.2
    for pid in $(pgrep -f build-omp/miniapps/bake/bake); do
      r=$(tr '\0' '\n' < /proc/$pid/environ 2>/dev/null | grep '^OMPI_COMM_WORLD_RANK=' | cut -d= -f2)
      [ -n "$r" ] && { echo "rank $r pid $pid from $(taskset -pc $pid | awk '{print $NF}') to $(( (r + 8) % 16 ))"; taskset -a -pc $(( (r + 8) % 16 )) $pid > /dev/null; }
    done > $T/$name.moves
  fi
  wait $mp || echo "$name failed"
}
for i in 1 2 3; do run16 rotate_$i rotate; run16 still_$i still; echo "round $i $(( $(date +%s)-t0 )) s"; done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort > $OUT/times.txt; cat $OUT/times.txt; head -3 $T/rotate_1.moves
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.json' -o -name '*.moves' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
