# Call C: main's bake and sketchtrace on CUDA: the bake ctests at 1-4 ranks (pairwise exchanges,
# resident report by kind: first CUDA run), then the mini-apps' GPU figures.
set -u
source .carry/dev_cuda.sh
t0=$(date +%s); el() { echo "[$(($(date +%s)-t0)) s] $*"; }
{ cat .carry/commit.txt; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
build_kokkos_cuda || exit 1
B=/tmp/b
cuda_configure $B $R -DRTMINI_ENABLE_TESTS=ON > /tmp/cfg.log 2>&1 || tail -20 /tmp/cfg.log
cmake --build $B -j 16 --target bake rtmini-gen-inputs rtmini_unit_bsb rtmini_unit_bake rtmini-input-bunny > /tmp/b1.log 2>&1 || grep -m5 -A8 error /tmp/b1.log
el bake built
(cmake --build $B -j 12 --target sketchtrace > /tmp/b2.log 2>&1; echo "sketch rc=$?" > /tmp/b2.rc) &
sk=$!
(cd $B && timeout 300 ctest -j 4 --timeout 200 -R '^(unit\.bake$|bake\.(furnace|restart\.np|binary_output|decomposition|distributed|hemisphere|timings)|faults\.one_rank\.bake)' > $OUT/ctest_bake_cuda.txt 2>&1; echo "ctest rc=$?"; grep -E "tests passed|Failed|\*\*\*" $OUT/ctest_bake_cuda.txt | head -20)
el ctest
wait $sk; cat /tmp/b2.rc; el sketch built
mkdir -p /tmp/o; F=$OUT/figures.txt
fig() { local n=$1; shift; echo "== $n: $*" >> $F; local s=$(date +%s.%N); timeout 100 "$@" >> $F 2>&1; echo "rc=$? wall $(echo "$(date +%s.%N) - $s" | bc) s" >> $F; }
for r in 1 2; do fig bake_bunny_room_$r $B/miniapps/bake/bake $B/inputs/bunny/bunny_room.bs -o /tmp/o/b.bsb --viewpoints 1000 --iterations 4; done
for r in 1 2 3; do fig ao_dragon_x4_$r $B/miniapps/bake/bake ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/o/d.glb; done
el ao
for r in 1 2; do fig st_4k_$r $B/miniapps/sketchtrace/sketchtrace inputs/two_spheres/two_spheres.toml --width 3840 --height 2160 --shadow-samples 1024 -o /tmp/o/4k.png; done
fig st_dist $B/miniapps/sketchtrace/sketchtrace inputs/dist_first/dist_first.toml --width 1000 --height 800 --spp 32 -o /tmp/o/d.png
grep -E "^==|bake time|whole bake|hash|verification|render time|rc=" $F | cut -c1-200
el end
