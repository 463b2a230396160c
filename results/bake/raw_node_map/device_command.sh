# Issue 19, twenty-fifth round (16-core host, OpenMP): the node's one map (--node-map on, the
# default with --node-sharing on and every rank on one node) against per-rank maps and halos
# (--node-map off), alternated per round: strong bunny_room N = 300 K = 4 at 1 x 16, 16 x 1
# (both variants), 8 x 2, 4 x 4, 2 x 8 (node map); weak 1 room / 16 rooms N = 200 K = 3 (both
# variants at 16); one 1 x 1 bake of bunny_room at the end.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; df -h /dev/shm | tail -1; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp || exit 3
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -30 $OUT/omp_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1 || { grep -m5 -A5 " error" $OUT/omp_build.log; exit 3; }
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
for i in 1 2 3 4 5 6; do
  [ $(( $(date +%s)-t0 )) -lt 400 ] || break
  go s1x16_node_$i 1 16 "${strong[@]}"
  go s16x1_node_$i 16 1 "${strong[@]}" --node-sharing on
  go s16x1_halo_$i 16 1 "${strong[@]}" --node-sharing on --node-map off
  for pt in 8x2 4x4 2x8; do go s${pt}_node_$i ${pt%x*} ${pt#*x} "${strong[@]}" --node-sharing on; done
  go w1_node_$i 1 1 /tmp/rooms_1.bs "${weak[@]}"
  go w16_node_$i 16 1 /tmp/rooms_16.bs "${weak[@]}"
  go w16_halo_$i 16 1 /tmp/rooms_16.bs "${weak[@]}" --node-map off
  echo "round $i $(( $(date +%s)-t0 )) s"
done
go s1x1_node_1 1 1 "${strong[@]}"
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/device_provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
