# Issue 19, twenty-second round: this tree's bake (colours in storage order) against 8b2462e's
# (Fibonacci order), in one call: weak 1 room / 16 rooms on, the host's ceiling (16 concurrent
# 1-room bakes), strong 1 x 16 / 16 x 1 on, and this tree's 1 x 1.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt), base 8b2462e"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/device_provenance.txt 2>&1
build_kokkos_omp
mkdir -p /tmp/base && tar xzf .carry/base-src.tgz -C /tmp/base
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -20 $OUT/omp_cfg.log; exit 3; }
omp_configure /tmp/base/build /tmp/base > $OUT/base_cfg.log 2>&1 || { tail -20 $OUT/base_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1 && cmake --build /tmp/base/build -j 16 --target bake > $OUT/base_build.log 2>&1; echo "builds rc=$? $(( $(date +%s)-t0 )) s"
NEW=$R/build-omp/miniapps/bake/bake; OLD=/tmp/base/build/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-omp/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
python3 .carry/results/bake/make_rooms_scene.py 1 /tmp/rooms_1.bs; python3 .carry/results/bake/make_rooms_scene.py 16 /tmp/rooms_16.bs
go() {  # go NAME BIN RANKS THREADS ARGS...
  local name=$1 bin=$2 p=$3 t=$4; shift 4
  OMP_NUM_THREADS=$t mpirun -n $p --map-by slot:PE=$t --bind-to core $bin "$@" -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
busy() {  # busy NAME BIN: 16 concurrent 1-room bakes, one core each
  local name=$1 bin=$2 i
  for i in $(seq 0 15); do
    OMP_NUM_THREADS=1 taskset -c $i mpirun -n 1 --bind-to none $bin /tmp/rooms_1.bs --viewpoints 200 --iterations 3 -o /tmp/${name}_$i.bsb > $T/${name}_$i.log 2>&1 &
  done; wait; rm -f /tmp/${name}_*.bsb
}
strong=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4)
weak=(--viewpoints 200 --iterations 3 --node-sharing on)
for i in 1 2 3; do
  go w1_new_$i $NEW 1 1 /tmp/rooms_1.bs "${weak[@]}"
  go w16_new_$i $NEW 16 1 /tmp/rooms_16.bs "${weak[@]}"
  go w1_old_$i $OLD 1 1 /tmp/rooms_1.bs "${weak[@]}"
  go w16_old_$i $OLD 16 1 /tmp/rooms_16.bs "${weak[@]}"
  echo "weak round $i $(( $(date +%s)-t0 )) s"
done
busy busy_new $NEW; busy busy_old $OLD; echo "busy $(( $(date +%s)-t0 )) s"
for i in 1 2 3; do
  go s1x16_new_$i $NEW 1 16 "${strong[@]}"
  go s16x1_new_$i $NEW 16 1 "${strong[@]}" --node-sharing on
  go s1x16_old_$i $OLD 1 16 "${strong[@]}"
  go s16x1_old_$i $OLD 16 1 "${strong[@]}" --node-sharing on
  echo "strong round $i $(( $(date +%s)-t0 )) s"
done
[ $(( $(date +%s)-t0 )) -lt 470 ] && go s1x1_new_1 $NEW 1 1 "${strong[@]}"
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/device_provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
