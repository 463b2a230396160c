# Device call: CUDA build of the tree in .gpuwt (a trial merge of the helpers' branches), its unit
# ctests, every bundled sketchtrace scene at 320x240 on the GPU, bake on 2 ranks sharing the GPU.
source .carry/dev_env.sh
cd .gpuwt
t0=$(date +%s); echo "commit $(cat ../.carry/commit_check.txt)" | tee $OUT/provenance.txt; date -u >> $OUT/provenance.txt
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader >> $OUT/provenance.txt
ompi_info --parsable --all 2>/dev/null | grep -i "cuda_support" | head -3 | tee -a $OUT/provenance.txt
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
cmake --build build-cuda -j 16 -- -k 0 > $OUT/build_cuda.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E 'error' -A3 $OUT/build_cuda.log | head -60
(cd build-cuda && ctest -L unit --timeout 300 -j 8 2>&1 | tee $OUT/unit_cuda.txt | grep -E "tests passed|Failed|Not Run" | head -20)
(cd build-cuda && ctest -R "sketchtrace\.(reference|same_hash|motion_balance)|regression\.ao|bake\.render\.cli" --timeout 300 -j 8 2>&1 | tee $OUT/regress_cuda.txt | grep -E "tests passed|Failed|Not Run" | head -30)
st=build-cuda/miniapps/sketchtrace/sketchtrace
for f in $(ls inputs/*/*.toml inputs/*/*.gltf 2>/dev/null); do
  timeout 60 $st "$f" --width 320 --height 240 -o /tmp/s_$(basename $f).ppm --summary /tmp/s_$(basename $f).json > /tmp/s_$(basename $f).log 2>&1
  echo "sketchtrace $f rc=$? $(grep -o '"verification_hash"[^,]*' /tmp/s_$(basename $f).json 2>/dev/null) $(tail -1 /tmp/s_$(basename $f).log | cut -c1-150)"
done | tee $OUT/sketchtrace_cuda.txt
g=build-cuda/inputs/rtmini-gen-inputs; $g bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/br.bs > /dev/null
for env in "" "RTMINI_MPI_DEVICE_BUFFERS=0"; do for np in 1 2; do
  env $env mpirun -n $np build-cuda/miniapps/bake/bake /tmp/br.bs -o /tmp/br.bsb --viewpoints 100 --iterations 3 --summary /tmp/br_$np.json > /tmp/br.log 2>&1
  echo "bake np=$np $env rc=$? $(grep -o '"verification_hash"[^,]*\|"exchange_buffers"[^,]*' /tmp/br_$np.json | tr '\n' ' ') $(grep 'bake time' /tmp/br.log)"
done; done | tee $OUT/bake_cuda.txt
tar czf $OUT/logs.tgz -C /tmp $(cd /tmp && ls s_*.log s_*.json br*.log br_*.json 2>/dev/null)
echo "total $(( $(date +%s)-t0 )) s"
