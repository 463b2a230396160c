# Issue 19, twenty-third round, call 1 (16-core host, OpenMP): the grid viewpoint lookup against
# the KD-tree in one binary (--lookup grid / kdtree, the same map), alternated per round: weak
# 1 room / 16 rooms (--node-sharing on), strong bunny_room N = 300 K = 4 1 x 16 / 16 x 1 on,
# 1 x 1 of each; then rtmini-bake-lookup-bench on 1 and 16 threads.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp || exit 3; echo "kokkos $(( $(date +%s)-t0 )) s"
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -30 $OUT/omp_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs rtmini-bake-lookup-bench > $OUT/omp_build.log 2>&1 || { grep -m5 -A5 " error" $OUT/omp_build.log; tail -20 $OUT/omp_build.log; exit 3; }
echo "build $(( $(date +%s)-t0 )) s"
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
python3 .carry/make_rooms_scene.py 1 /tmp/rooms_1.bs; python3 .carry/make_rooms_scene.py 16 /tmp/rooms_16.bs
go() {  # go NAME RANKS THREADS ARGS...
  local name=$1 p=$2 t=$3; shift 3
  OMP_NUM_THREADS=$t mpirun -n $p --map-by slot:PE=$t --bind-to core $B "$@" -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
strong=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4)
weak=(--viewpoints 200 --iterations 3 --node-sharing on)
for i in 1 2 3; do
  for lk in grid kdtree; do
    go w1_${lk}_$i 1 1 /tmp/rooms_1.bs "${weak[@]}" --lookup $lk
    go w16_${lk}_$i 16 1 /tmp/rooms_16.bs "${weak[@]}" --lookup $lk
    go s1x16_${lk}_$i 1 16 "${strong[@]}" --lookup $lk
    go s16x1_${lk}_$i 16 1 "${strong[@]}" --node-sharing on --lookup $lk
  done
  echo "round $i $(( $(date +%s)-t0 )) s"
done
for lk in grid kdtree; do [ $(( $(date +%s)-t0 )) -lt 440 ] && go s1x1_${lk}_1 1 1 "${strong[@]}" --lookup $lk; done
[ $(( $(date +%s)-t0 )) -lt 500 ] && OMP_NUM_THREADS=16 build-omp/miniapps/bake/rtmini-bake-lookup-bench 2000000 > $OUT/lookup_bench_16t.txt 2>&1
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/device_provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
