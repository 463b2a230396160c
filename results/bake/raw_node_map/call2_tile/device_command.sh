# Issue 19, twenty-fifth round, call 2 (16-core host, OpenMP): the slot-major tiles of the mirror
# iterations' walk (--item-tile 32, the tree's default) against the vertex-major walk
# (--item-tile 1), one binary, alternated per round: bunny_room N = 300 K = 4 at 1 x 16 and
# 16 x 1 (--node-sharing on), one 1 x 1 of each; then the host's compute-only clock ceiling
# (one FP-bound loop alone against 16 concurrent copies, one per core).
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp || exit 3
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -30 $OUT/omp_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1 || { grep -m5 -A5 " error" $OUT/omp_build.log; exit 3; }
g++ -O2 -o /tmp/clock_ceiling .carry/clock_ceiling.cpp
echo "build $(( $(date +%s)-t0 )) s"
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
go() {  # go NAME RANKS THREADS ARGS...
  local name=$1 p=$2 t=$3; shift 3
  OMP_NUM_THREADS=$t mpirun -n $p --map-by slot:PE=$t --bind-to core $B "$@" -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
strong=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4)
for i in 1 2 3 4 5 6 7 8; do
  [ $(( $(date +%s)-t0 )) -lt 290 ] || break
  go s1x16_tile_$i 1 16 "${strong[@]}" --item-tile 32
  go s1x16_vert_$i 1 16 "${strong[@]}" --item-tile 1
  go s16x1_tile_$i 16 1 "${strong[@]}" --node-sharing on --item-tile 32
  go s16x1_vert_$i 16 1 "${strong[@]}" --node-sharing on --item-tile 1
  echo "round $i $(( $(date +%s)-t0 )) s"
done
go s1x1_tile_1 1 1 "${strong[@]}" --item-tile 32
go s1x1_vert_1 1 1 "${strong[@]}" --item-tile 1
for r in 1 2 3; do
  echo "round $r alone: $(taskset -c 0 /tmp/clock_ceiling)" >> $OUT/clock_ceiling.txt
  for c in $(seq 0 15); do taskset -c $c /tmp/clock_ceiling > /tmp/cc_$c.txt & done; wait
  echo "round $r 16 copies: $(cat /tmp/cc_*.txt | cut -d' ' -f1 | sort -n | tr '\n' ' ')" >> $OUT/clock_ceiling.txt
done
cat $OUT/clock_ceiling.txt
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/device_provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
