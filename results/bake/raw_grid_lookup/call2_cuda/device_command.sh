# Issue 19, twenty-third round, call 2 (H200, CUDA): the grid viewpoint lookup against the
# KD-tree in one binary (the same map on one backend), alternated: bunny_room N = 300 and 1000,
# K = 4; one room N = 200 K = 3; a hemisphere map; 2 ranks on the GPU; the lookup bench.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; nvcc --version | tail -2; } > $OUT/device_provenance.txt 2>&1
build_kokkos_cuda || exit 3; echo "kokkos $(( $(date +%s)-t0 )) s"
cuda_configure build-cuda > $OUT/cuda_cfg.log 2>&1 || { tail -30 $OUT/cuda_cfg.log; exit 3; }
cmake --build build-cuda -j 16 --target bake rtmini-gen-inputs rtmini-bake-lookup-bench > $OUT/cuda_build.log 2>&1 || { grep -m5 -A8 " error" $OUT/cuda_build.log; tail -20 $OUT/cuda_build.log; exit 3; }
echo "build $(( $(date +%s)-t0 )) s"
B=$R/build-cuda/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-cuda/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
for p in 1 2; do python3 .carry/make_rooms_scene.py $p /tmp/rooms_$p.bs; done
go() {  # go NAME RANKS ARGS...
  local name=$1 p=$2; shift 2
  mpirun -n $p --bind-to none $B "$@" -o /tmp/$name.bsb --summary $T/$name.json > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
for i in 1 2 3 4; do
  [ $(( $(date +%s)-t0 )) -lt 500 ] || break
  for lk in grid kdtree; do
    go b1000_${lk}_$i 1 /tmp/bunny_room.bs --viewpoints 1000 --iterations 4 --lookup $lk
    go b300_${lk}_$i 1 /tmp/bunny_room.bs --viewpoints 300 --iterations 4 --lookup $lk
    go r1_${lk}_$i 1 /tmp/rooms_1.bs --viewpoints 200 --iterations 3 --lookup $lk
  done
  echo "round $i $(( $(date +%s)-t0 )) s"
done
for lk in grid kdtree; do
  go hemi_${lk} 1 /tmp/bunny_room.bs --viewpoints 300 --iterations 4 --directions hemisphere --lookup $lk
  go r2x2_${lk} 2 /tmp/rooms_2.bs --viewpoints 200 --iterations 3 --lookup $lk
done
[ $(( $(date +%s)-t0 )) -lt 540 ] && timeout 50 build-cuda/miniapps/bake/rtmini-bake-lookup-bench 4000000 > $OUT/lookup_bench_cuda.txt 2>&1
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
