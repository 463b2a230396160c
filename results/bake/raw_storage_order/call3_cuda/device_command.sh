# Issue 19, twenty-second round, call 3 (CUDA, H200): this tree's bake (storage order + ColorSpan)
# against 8b2462e's, one GPU: bunny_room N = 300 and 1000, K = 4; one room N = 200, K = 3;
# alternated, four rounds. Then correctness of the new paths on CUDA: 2 ranks on the GPU
# (halo, spans), a stop + restart against the uninterrupted run; hashes against the base.
source .carry/dev_cuda.sh
t0=$(date +%s)
{ echo "tree $(cat .carry/commit.txt), base 8b2462e"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/device_provenance.txt 2>&1
build_kokkos_cuda || exit 3
mkdir -p /tmp/base && tar xzf .carry/base-src.tgz -C /tmp/base
cuda_configure build-cuda > $OUT/cuda_cfg.log 2>&1 || { tail -20 $OUT/cuda_cfg.log; exit 3; }
cuda_configure /tmp/base/build-cuda /tmp/base > $OUT/base_cfg.log 2>&1 || { tail -20 $OUT/base_cfg.log; exit 3; }
cmake --build build-cuda -j 8 --target bake rtmini-gen-inputs > $OUT/cuda_build.log 2>&1 &
cmake --build /tmp/base/build-cuda -j 8 --target bake > $OUT/base_build.log 2>&1; wait
echo "builds $(( $(date +%s)-t0 )) s"; grep -m3 -A3 " error" $OUT/cuda_build.log $OUT/base_build.log
NEW=$R/build-cuda/miniapps/bake/bake; OLD=/tmp/base/build-cuda/miniapps/bake/bake; T=$OUT/runs; mkdir -p $T
build-cuda/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
for p in 1 2; do python3 .carry/results/bake/make_rooms_scene.py $p /tmp/rooms_$p.bs; done
go() {  # go NAME BIN RANKS ARGS...
  local name=$1 bin=$2 p=$3; shift 3
  mpirun -n $p --bind-to none $bin "$@" -o /tmp/$name.bsb --summary $T/$name.json > $T/$name.log 2>&1 || echo "$name failed rc=$?"
  rm -f /tmp/$name.bsb
}
for i in 1 2 3 4; do
  [ $(( $(date +%s)-t0 )) -lt 480 ] || break
  for v in new old; do bin=$NEW; [ $v = old ] && bin=$OLD
    go b1000_${v}_$i $bin 1 /tmp/bunny_room.bs --viewpoints 1000 --iterations 4
    go b300_${v}_$i $bin 1 /tmp/bunny_room.bs --viewpoints 300 --iterations 4
    go r1_${v}_$i $bin 1 /tmp/rooms_1.bs --viewpoints 200 --iterations 3
  done
  echo "round $i $(( $(date +%s)-t0 )) s"
done
go r2x2_new $NEW 2 /tmp/rooms_2.bs --viewpoints 200 --iterations 3
go r2x2_old $OLD 2 /tmp/rooms_2.bs --viewpoints 200 --iterations 3
go stop_new $NEW 2 /tmp/rooms_2.bs --viewpoints 200 --iterations 3 --checkpoint /tmp/cp.h5 --stop-after-iteration 1
go restart_new $NEW 2 /tmp/rooms_2.bs --viewpoints 200 --iterations 3 --checkpoint /tmp/cp.h5 --restart /tmp/cp.h5
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done | sort -V > $OUT/times.txt; cat $OUT/times.txt
find $OUT -name '*.txt' -o -name '*.log' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/|TMP/|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
