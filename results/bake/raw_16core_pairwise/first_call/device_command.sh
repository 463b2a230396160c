# Issue 19, memory at 16 ranks: where the peak's unaccounted rest lives (heap, files, shared
# memory) and whether the MPI transport sets it; then the strong-scaling table again.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; } > $OUT/provenance.txt
omp_configure build-omp-m14 > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp-m14 -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "build rc=$? $(( $(date +%s)-t0 )) s"
mkdir -p build/inputs build/miniapps/bake && ln -sf $R/build-omp-m14/inputs/rtmini-gen-inputs build/inputs/rtmini-gen-inputs && ln -sf $R/build-omp-m14/miniapps/bake/bake build/miniapps/bake/bake
ompi_info | grep -E "MCA (pml|btl|osc)" > $OUT/ompi_transports.txt
B=$R/build-omp-m14/miniapps/bake/bake; T=$OUT/transport; mkdir -p $T
build/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o TMP/bunny_room.bs > /dev/null
mpirun -n 16 --map-by slot:PE=1 --bind-to core --mca pml_base_verbose 10 --mca btl_base_verbose 10 $B TMP/bunny_room.bs -o TMP/v.bsb --viewpoints 20 --iterations 2 2>&1 | grep -iE "select|using|priority" | sort | uniq -c | sort -rn | head -20 > $OUT/pml_selected.txt
for i in 1 2; do
  for tr in default "ob1:--mca pml ob1 --mca btl self,vader" "ucx:--mca pml ucx"; do
    name=${tr%%:*}; args=""; [ "$name" = default ] || args=${tr#*:}
    OMP_NUM_THREADS=1 /usr/bin/time -f "wall %e s" -o $T/${name}_16x1_$i.time mpirun -n 16 --map-by slot:PE=1 --bind-to core $args $B TMP/bunny_room.bs -o TMP/t.bsb --viewpoints 300 --iterations 4 --summary $T/${name}_16x1_$i.json > $T/${name}_16x1_$i.log 2>&1; echo "$name $i rc=$? $(( $(date +%s)-t0 )) s"
  done
done
python3 results/bake/raw_memory10/resident.py $T/*.json > $OUT/transport_resident.md; cat $OUT/transport_resident.md
grep -h "bake time\|verification" $T/*.log | sort | uniq -c | head -20
[ $(( $(date +%s)-t0 )) -lt 330 ] && timeout 230 bash results/bake/run_distributed.sh $OUT/scaling scaling > $OUT/scaling.txt 2>&1; echo "scaling rc=$? $(( $(date +%s)-t0 )) s"
[ -f $OUT/scaling/table.md ] && grep -A9 'Strong scaling in one run' $OUT/scaling/table.md | tail -7
python3 results/bake/raw_memory10/resident.py $OUT/scaling/scaling_*_1.json > $OUT/scaling_resident.md 2>&1; cat $OUT/scaling_resident.md
rm -f $OUT/*/*.bs $OUT/*/*.bsb $OUT/*/*.h5
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.md' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|$OUT|OUT|g" 2>/dev/null
echo "total $(( $(date +%s)-t0 )) s"
