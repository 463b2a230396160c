# Issue 19, twenty-fourth round (16-core host, OpenMP): the node-shared mirror trace (this tree)
# against 67bfb79 (per-rank trace, hits copied into the window at iteration 1), alternated per
# round: weak 16 rooms 16 x 1 on (and 1 room, the same code on both), strong bunny_room N = 300
# K = 4 16 x 1 on (and 1 x 16, 1 x 1 on this tree), all with the grid lookup.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt), base 67bfb79"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp || exit 3
mkdir -p /tmp/base && tar xzf .carry/base-src.tgz -C /tmp/base
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -30 $OUT/omp_cfg.log; exit 3; }
omp_configure /tmp/base/build /tmp/base > $OUT/base_cfg.log 2>&1 || { tail -30 $OUT/base_cfg.log; exit 3; }
cmake --build build-omp -j 8 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1 &
cmake --build /tmp/base/build -j 8 --target bake > $OUT/base_build.log 2>&1; wait
grep -m3 -A5 " error" $OUT/omp_build.log $OUT/base_build.log; echo "builds $(( $(date +%s)-t0 )) s"
NEW=$R/build-omp/miniapps/bake/bake; OLD=/tmp/base/build/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
python3 .carry/make_rooms_scene.py 1 /tmp/rooms_1.bs; python3 .carry/make_rooms_scene.py 16 /tmp/rooms_16.bs
go() {  # go NAME BIN RANKS THREADS ARGS...
  local name=$1 bin=$2 p=$3 t=$4; shift 4
  OMP_NUM_THREADS=$t mpirun -n $p --map-by slot:PE=$t --bind-to core $bin "$@" -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
strong=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4)
weak=(--viewpoints 200 --iterations 3 --node-sharing on)
for i in 1 2 3; do
  go w1_new_$i $NEW 1 1 /tmp/rooms_1.bs "${weak[@]}"
  go w16_new_$i $NEW 16 1 /tmp/rooms_16.bs "${weak[@]}"
  go w16_old_$i $OLD 16 1 /tmp/rooms_16.bs "${weak[@]}"
  go s1x16_new_$i $NEW 1 16 "${strong[@]}"
  go s16x1_new_$i $NEW 16 1 "${strong[@]}" --node-sharing on
  go s16x1_old_$i $OLD 16 1 "${strong[@]}" --node-sharing on
  echo "round $i $(( $(date +%s)-t0 )) s"
done
[ $(( $(date +%s)-t0 )) -lt 480 ] && go s1x1_new_1 $NEW 1 1 "${strong[@]}"
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/device_provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
