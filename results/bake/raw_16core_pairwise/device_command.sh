# Issue 19: pairwise exchanges (branch) against MPI_Ialltoallv (base = its parent) at 2x8..16x1,
# alternated, memory by kind and bake time; plus the shared-memory transport's single-copy setting.
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "branch $(cat .carry/commit.txt), base $(cat .carry/base_commit.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; mpirun --version | head -1; } > $OUT/provenance.txt
rm -rf /tmp/base-src; mkdir -p /tmp/base-src && tar xzf .carry/base-src.tgz -C /tmp/base-src
omp_configure build-omp-b14 > $OUT/omp_cfg.log 2>&1 && cmake --build build-omp-b14 -j 16 --target bake rtmini-gen-inputs > $OUT/omp_build.log 2>&1; echo "branch build rc=$? $(( $(date +%s)-t0 )) s"
( cd /tmp/base-src && cp -r $R/.carry . && omp_configure $R/build-omp-a14 > $OUT/base_cfg.log 2>&1 && cmake --build $R/build-omp-a14 -j 16 --target bake > $OUT/base_build.log 2>&1 ); echo "base build rc=$? $(( $(date +%s)-t0 )) s"
ompi_info --param btl vader --level 9 | grep -iE "single_copy|eager_limit|max_send|fbox" > $OUT/vader_params.txt
cat /proc/sys/kernel/yama/ptrace_scope >> $OUT/vader_params.txt 2>&1
build-omp-b14/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o /tmp/bunny_room.bs > /dev/null
T=$OUT/runs; mkdir -p $T
run() {  # run NAME BIN NP T [mpirun args]
  local name=$1 bin=$2 np=$3 t=$4; shift 4
  OMP_NUM_THREADS=$t /usr/bin/time -f "wall %e s" -o $T/$name.time mpirun -n $np --map-by slot:PE=$t --bind-to core "$@" $bin /tmp/bunny_room.bs -o /tmp/t.bsb --viewpoints 300 --iterations 4 --summary $T/$name.json > $T/$name.log 2>&1 || echo "$name failed"
}
for i in 1 2 3; do
  for pt in 16x1 8x2 4x4 2x8 1x16; do
    for b in a2a:build-omp-a14 pair:build-omp-b14; do
      [ $(( $(date +%s)-t0 )) -lt 440 ] || break 3
      run ${b%%:*}_${pt}_$i $R/${b#*:}/miniapps/bake/bake ${pt%x*} ${pt#*x}
    done
  done
  echo "round $i $(( $(date +%s)-t0 )) s"
done
[ $(( $(date +%s)-t0 )) -lt 500 ] && run a2a_cma_16x1 $R/build-omp-a14/miniapps/bake/bake 16 1 --mca btl_vader_single_copy_mechanism cma
[ $(( $(date +%s)-t0 )) -lt 510 ] && run pair_cma_16x1 $R/build-omp-b14/miniapps/bake/bake 16 1 --mca btl_vader_single_copy_mechanism cma
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
python3 results/bake/raw_memory10/resident.py $T/*.json > $OUT/resident.md; cat $OUT/resident.md | cut -c1-400
for f in $T/*.log; do echo "$(basename $f .log) $(grep -o 'bake time [0-9.]* s' $f) $(grep -o 'verification [0-9a-f]*' $f)"; done > $OUT/times.txt; cat $OUT/times.txt
cat $OUT/vader_params.txt
find $OUT -name '*.txt' -o -name '*.log' -o -name '*.md' -o -name '*.json' | xargs sed -i "s|$(pwd)|.|g; s|/tmp/base-src|BASE_SRC|g; s|$OUT|OUT|g" 2>/dev/null
(cd $OUT && tar czf /tmp/runs.tgz runs && rm -rf runs && mv /tmp/runs.tgz .)
echo "total $(( $(date +%s)-t0 )) s"
