# Issue 19, twenty-fifth round, call 5 (16-core host, OpenMP): a job across nodes, simulated by
# the test hook RTMINI_TEST_RANKS_PER_NODE=4 (four nodes of four ranks on the one host):
# each node's one map with halos of the other nodes (--node-map on) against per-rank maps and
# halos (--node-map off), --node-sharing on, alternated: bunny_room N = 300 K = 4 at 16 x 1, then
# 16 rooms N = 200 K = 3 at 16 x 1 as time allows.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp || exit 3
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -30 $OUT/omp_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1 || { grep -m5 -A5 " error" $OUT/omp_build.log; exit 3; }
echo "build $(( $(date +%s)-t0 )) s"
B=$R/build-omp/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
python3 .carry/make_rooms_scene.py 16 /tmp/rooms_16.bs
go() {  # go NAME ARGS...: 16 x 1 on four nodes of four ranks
  local name=$1; shift
  RTMINI_TEST_RANKS_PER_NODE=4 OMP_NUM_THREADS=1 mpirun -x RTMINI_TEST_RANKS_PER_NODE -n 16 --bind-to core $B "$@" --node-sharing on -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
  echo "$name $(grep -o 'bake time [0-9.]* s' $T/$name.log) $(grep -o 'verification [0-9a-f]*' $T/$name.log)" >> $OUT/times.txt
}
for i in 1 2 3 4; do
  [ $(( $(date +%s)-t0 )) -lt 165 ] || break
  go s16x1_node_$i /tmp/bunny_room.bs --viewpoints 300 --iterations 4 --node-map on
  go s16x1_halo_$i /tmp/bunny_room.bs --viewpoints 300 --iterations 4 --node-map off
done
for i in 1 2; do
  [ $(( $(date +%s)-t0 )) -lt 175 ] || break
  go w16_node_$i /tmp/rooms_16.bs --viewpoints 200 --iterations 3 --node-map on
  go w16_halo_$i /tmp/rooms_16.bs --viewpoints 200 --iterations 3 --node-map off
done
cat $OUT/times.txt; grep -h "map per rank" $T/*_1.log
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
