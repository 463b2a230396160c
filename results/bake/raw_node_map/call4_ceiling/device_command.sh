# Issue 19, twenty-fifth round, call 4 (16-core host, OpenMP): the host's ceiling for the issue's
# two 85 % rows, in the same call as the rows themselves: one 1 x 1 bunny_room bake (N = 300,
# K = 4) alone against 16 concurrent copies of it (one per core, no communication at all); one
# 1-room bake (N = 200, K = 3) alone against 16 concurrent copies; then 1 x 16, 16 x 1 `on` and
# 16 rooms 16 x 1 `on` (the node map). Three alternated rounds (two of the long bunny pair).
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/device_provenance.txt 2>&1
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
copies() {  # copies NAME ARGS...: 16 concurrent 1 x 1 bakes, one per core
  local name=$1; shift
  for c in $(seq 0 15); do OMP_NUM_THREADS=1 taskset -c $c $B "$@" -o /tmp/${name}_c$c.bsb > $T/${name}_c$c.log 2>&1 & done; wait
  rm -f /tmp/${name}_c*.bsb
}
strong=(/tmp/bunny_room.bs --viewpoints 300 --iterations 4)
weak=(--viewpoints 200 --iterations 3)
for i in 1 2 3; do
  [ $(( $(date +%s)-t0 )) -lt 420 ] || break
  go s1x16_new_$i 1 16 "${strong[@]}"
  go s16x1_new_$i 16 1 "${strong[@]}" --node-sharing on
  go w1_new_$i 1 1 /tmp/rooms_1.bs "${weak[@]}"
  copies w1copies_new_$i /tmp/rooms_1.bs "${weak[@]}"
  go w16_new_$i 16 1 /tmp/rooms_16.bs "${weak[@]}" --node-sharing on
  if [ $i -le 2 ]; then
    go s1x1_new_$i 1 1 "${strong[@]}"
    copies s1x1copies_new_$i "${strong[@]}"
  fi
  echo "round $i $(( $(date +%s)-t0 )) s"
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/device_provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt
grep -v "_c[0-9]" $OUT/times.txt
for g in $(ls $T | grep -o '^[a-z0-9]*copies_new_[0-9]*' | sort -u); do echo "$g $(grep "^${g}_c" $OUT/times.txt | grep -o 'time [0-9.]*' | cut -d' ' -f2 | sort -n | tr '\n' ' ')"; done > $OUT/copies.txt; cat $OUT/copies.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
