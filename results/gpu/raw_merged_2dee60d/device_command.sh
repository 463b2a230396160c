# Device call: CUDA build of the merged tree, its unit ctests, AO fit Cholesky vs CG on the H200.
source .carry/dev_env.sh
t0=$(date +%s); echo "commit $(cat .carry/commit.txt)" | tee $OUT/provenance.txt; date -u >> $OUT/provenance.txt
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader >> $OUT/provenance.txt
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg_cuda.log 2>&1 && cmake --build build-cuda -j 16 > $OUT/build_cuda.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E 'error' $OUT/build_cuda.log | head -20
(cd build-cuda && ctest -L unit --output-on-failure --timeout 300 -j 8 2>&1 | tee $OUT/unit_cuda.txt | tail -15)
for m in dragon stanford-bunny; do for w in "ao --quality sah" "ao --quality lbvh" "diffuse --quality sah"; do
  echo "== bench $m $w"; build-cuda/bench/rtmini-bvh-bench inputs/meshes/$m.obj --workload $w 2>&1 | grep -E "FOM|rays/s|hash|hit|per ray" | head -8
done; done > $OUT/bench.txt 2>&1; cat $OUT/bench.txt | grep -E "==|FOM|hash"
mkdir -p /tmp/o
for rep in 1 2 3; do for fit in cholesky cg; do
  build-cuda/miniapps/bake/bake ao inputs/ao/dragon_x4.toml -s 1250000 --fit $fit -o /tmp/o/dragon_$fit.bin --summary /tmp/o/dragon_${fit}_$rep.json > /tmp/o/ao_${fit}_$rep.log 2>&1
  grep -E "Whole bake|Map AO|verification" /tmp/o/ao_${fit}_$rep.log | sed "s/^/$fit rep$rep: /"
done; done
python3 results/ao/cg_fit/bin_diff.py /tmp/o/dragon_cholesky.bin /tmp/o/dragon_cg.bin
tar czf $OUT/ao_logs.tgz -C /tmp/o $(cd /tmp/o && ls *.log *.json)
echo "total $(( $(date +%s)-t0 )) s"
