# Issue 19, twenty-third round, call 3 (16-core host, OpenMP): the cost model's lookup weight
# with the grid lookup. bunny_room N = 300 K = 4 cut by the pilot (--balance pilot, no node
# sharing, so each rank's time is its own work) at 16 x 1, 8 x 2, 4 x 4, grid and KD-tree; the
# per-rank cached iterations are fitted against the colours and lookup hits each rank counted.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp || exit 3
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -30 $OUT/omp_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1 || { grep -m5 -A5 " error" $OUT/omp_build.log; exit 3; }
echo "build $(( $(date +%s)-t0 )) s"
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
go() {  # go NAME RANKS THREADS ARGS...
  local name=$1 p=$2 t=$3; shift 3
  OMP_NUM_THREADS=$t mpirun -n $p --map-by slot:PE=$t --bind-to core $B "$@" -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
strong=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4 --balance pilot --node-sharing off)
for i in 1 2; do
  for lk in grid kdtree; do
    for pt in 16x1 8x2 4x4; do go pilot${pt}_${lk}_$i ${pt%x*} ${pt#*x} "${strong[@]}" --lookup $lk; done
  done
  echo "round $i $(( $(date +%s)-t0 )) s"
done
for lk in grid kdtree; do go cost16x1_${lk}_1 16 1 /tmp/bunny_room.bs --viewpoints 300 --iterations 4 --node-sharing off --lookup $lk; done
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
