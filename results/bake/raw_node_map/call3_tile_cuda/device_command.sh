# Issue 19, twenty-fifth round, call 3 (H200, CUDA): the slot-major tiles of the mirror walk
# (--item-tile 32: a warp runs one viewpoint at 32 neighbouring vertices) against the
# vertex-major walk (--item-tile 1: a warp runs 32 viewpoints of one vertex), one binary,
# alternated: bunny_room N = 300 and 1000 K = 4, one room N = 200 K = 3, timings per iteration.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; nvcc --version | tail -2; } > $OUT/device_provenance.txt 2>&1
build_kokkos_cuda || exit 3; echo "kokkos $(( $(date +%s)-t0 )) s"
cuda_configure build-cuda > $OUT/cuda_cfg.log 2>&1 || { tail -30 $OUT/cuda_cfg.log; exit 3; }
cmake --build build-cuda -j 16 --target bake rtmini-gen-inputs > $OUT/cuda_build.log 2>&1 || { grep -m5 -A8 " error" $OUT/cuda_build.log; tail -20 $OUT/cuda_build.log; exit 3; }
echo "build $(( $(date +%s)-t0 )) s"
B=$R/build-cuda/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-cuda/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
python3 .carry/make_rooms_scene.py 1 /tmp/rooms_1.bs
go() {  # go NAME ARGS...
  local name=$1; shift
  mpirun -n 1 --bind-to none $B "$@" -o /tmp/$name.bsb --summary $T/$name.json --timings $T/$name.h5 > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
for i in 1 2 3 4 5; do
  [ $(( $(date +%s)-t0 )) -lt 480 ] || break
  for v in tile:32 vert:1; do
    go b1000_${v%:*}_$i /tmp/bunny_room.bs --viewpoints 1000 --iterations 4 --item-tile ${v#*:}
    go b300_${v%:*}_$i /tmp/bunny_room.bs --viewpoints 300 --iterations 4 --item-tile ${v#*:}
    go r1_${v%:*}_$i /tmp/rooms_1.bs --viewpoints 200 --iterations 3 --item-tile ${v#*:}
  done
  echo "round $i $(( $(date +%s)-t0 )) s"
done
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
