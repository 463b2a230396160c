# Device call: OpenMP build of the tree in .bakewt, then the four long-running programs at once,
# each on its own core with 1 thread (a quiet host: wall clock = the program's own progress), for
# the ETA tables of results/progress (issue 16).
source .carry/dev_env.sh
R=$(pwd); cd "$R"
t0=$(date +%s)
cmake -S . -B build-eta "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-omp -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg.log 2>&1 || { tail -20 $OUT/cfg.log; exit 1; }
cmake --build build-eta -j 16 --target bake sketchtrace > $OUT/build.log 2>&1 || { grep error $OUT/build.log | head; exit 1; }
echo "build $(( $(date +%s)-t0 )) s"
{ echo "commit $(cat .carry/commit_eta.txt)"; date -u; echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"; echo "load before $(cut -d' ' -f1-3 /proc/loadavg)"; } > $OUT/provenance.txt
mkdir -p /tmp/eta && cd /tmp/eta
B=$R/build-eta/miniapps/bake/bake S=$R/build-eta/miniapps/sketchtrace/sketchtrace
C="python3 $R/results/progress/cpu_clock.py"
export OMP_PROC_BIND=false
$B $R/inputs/cornell_big/cornell_big_raw.bs -o map.bs --viewpoints 1000 --iterations 4 --shadow-samples 16 --threads 16 > /dev/null
printf '[camera]\nposition = [0, 1, 3.9]\nlook_at = [0, 1, 0]\nup = [0, 1, 0]\nfov_deg = 40\n[[meshes]]\nfile = "%s"\n' "$R/inputs/cornell_big/cornell_big_raw.bs" > front.toml
echo "runs start $(( $(date +%s)-t0 )) s"
[ "${ONLY:-}" ] || taskset -c 2 timeout 420 $C render.log $B render map.bs --scene front.toml --width 1280 --height 960 --spp 512 --threads 1 --progress -o r.ppm > render.stdout &
[ "${ONLY:-}" ] || taskset -c 5 timeout 420 $C ao.log $B ao $R/inputs/meshes/dragon.obj --rays 1280 --threads 1 --progress > ao.stdout &
taskset -c 8 timeout 420 $C sketchtrace.log $S $R/inputs/watchtower/watchtower.toml --width ${SKW:-1700} --height ${SKH:-1275} --threads 1 --progress -o w.ppm > sketchtrace.stdout &
taskset -c 11 timeout 420 $C bake.log $B $R/inputs/cornell_big/cornell_big_raw.bs -n ${BN:-1000} -k ${BK:-5} --gather-rays ${BG:-1200} --batch-size 64 -o cb.bs --threads 1 --progress > bake.stdout &
wait
echo "load after $(cut -d' ' -f1-3 /proc/loadavg)" >> $OUT/provenance.txt
cp *.log $OUT/; for f in *.log; do echo "$f: $(tail -1 $f | cut -c1-160)"; done
python3 $R/results/progress/eta_table.py *.log 2>&1 | grep -E "^\| (run|results|render|ao|sketch|bake)|worst|^results" | head -20
echo "total $(( $(date +%s)-t0 )) s"
