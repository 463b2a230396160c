# Issue 19, twenty-second round, call 2: this tree's bake (one ColorSpan record per vertex)
# against e1a6216's (three per-vertex tables), weak 1 / 2 / 16 rooms, and 16 rooms without
# node sharing (heap memory instead of the node's shared window).
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt), base e1a6216"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)";
  for f in enabled shmem_enabled defrag; do echo "thp $f: $(cat /sys/kernel/mm/transparent_hugepage/$f 2>&1)"; done
  lscpu | grep -iE "numa|socket|thread|L2|L3|MHz"; df -h /dev/shm | tail -1; } > $OUT/device_provenance.txt 2>&1
cat $OUT/device_provenance.txt
build_kokkos_omp
mkdir -p /tmp/base && tar xzf .carry/base-src.tgz -C /tmp/base
omp_configure build-omp > $OUT/omp_cfg.log 2>&1 || { tail -20 $OUT/omp_cfg.log; exit 3; }
omp_configure /tmp/base/build /tmp/base > $OUT/base_cfg.log 2>&1 || { tail -20 $OUT/base_cfg.log; exit 3; }
cmake --build build-omp -j 16 --target bake > $OUT/omp_build.log 2>&1 && cmake --build /tmp/base/build -j 16 --target bake > $OUT/base_build.log 2>&1; echo "builds rc=$? $(( $(date +%s)-t0 )) s"
NEW=$R/build-omp/miniapps/bake/bake; OLD=/tmp/base/build/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
for p in 1 2 16; do python3 .carry/results/bake/make_rooms_scene.py $p /tmp/rooms_$p.bs; done
go() {  # go NAME BIN RANKS THREADS ARGS...
  local name=$1 bin=$2 p=$3 t=$4; shift 4
  OMP_NUM_THREADS=$t mpirun -n $p --map-by slot:PE=$t --bind-to core $bin "$@" -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
weak=(--viewpoints 200 --iterations 3)
for i in 1 2 3; do
  [ $(( $(date +%s)-t0 )) -lt 500 ] || break
  go w1_new_$i $NEW 1 1 /tmp/rooms_1.bs "${weak[@]}" --node-sharing on
  go w16_new_$i $NEW 16 1 /tmp/rooms_16.bs "${weak[@]}" --node-sharing on
  go w16_old_$i $OLD 16 1 /tmp/rooms_16.bs "${weak[@]}" --node-sharing on
  go w16off_new_$i $NEW 16 1 /tmp/rooms_16.bs "${weak[@]}" --node-sharing off
  go w2_new_$i $NEW 2 1 /tmp/rooms_2.bs "${weak[@]}" --node-sharing on
  echo "weak round $i $(( $(date +%s)-t0 )) s"
done
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/device_provenance.txt
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
