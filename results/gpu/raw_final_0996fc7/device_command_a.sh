# Device call A of two (back to back, same machine): CUDA build of every target of the repository
# root (the session's final merge), then the mini-apps' GPU figures (issue 21's list).
source .carry/dev_env.sh
t0=$(date +%s)
{ echo "commit $(cat .carry/commit_trial.txt)"; date -u; nvidia-smi --query-gpu=name,driver_version --format=csv,noheader; } > $OUT/provenance.txt
cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > $OUT/cfg_cuda.log 2>&1 || tail -30 $OUT/cfg_cuda.log
cmake --build build-cuda -j 16 -- -k 0 > $OUT/build_cuda.log 2>&1; echo "cuda build rc=$? $(( $(date +%s)-t0 )) s"
grep -E ' error' -A3 $OUT/build_cuda.log | head -30
mkdir -p /tmp/o; C=$OUT/commands.txt
r() { local tag=$1; shift; echo "== $tag: $*" >> $C; timeout 60 "$@" > $OUT/$tag.log 2>&1; echo "$tag rc=$? $(grep -E 'Whole bake|verification|render|bake \(|FOM' $OUT/$tag.log | tr -s ' ' | tr '\n' '|' | cut -c1-260)"; }
B=build-cuda/miniapps/bake/bake S=build-cuda/miniapps/sketchtrace/sketchtrace NB=build-cuda/bench/rtmini-bvh-bench
for rep in 1 2 3; do r ao_dragon_x4_rep$rep $B ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/o/d.glb; done
for rep in 1 2; do r st_4k_rep$rep $S inputs/two_spheres/two_spheres.toml --width 3840 --height 2160 --shadow-samples 1024 -o /tmp/o/4k.png; done
r st_dist $S inputs/dist_first/dist_first.toml --width 1000 --height 800 --spp 32 -o /tmp/o/d.png
r bake_bunny_room $B build-cuda/inputs/bunny/bunny_room.bs -o /tmp/o/b.bsb --viewpoints 1000 --iterations 4
for m in dragon stanford-bunny; do for q in sah lbvh ploc; do r bench_${m}_$q $NB inputs/meshes/$m.obj --workload ao --quality $q; done; done
echo "total $(( $(date +%s)-t0 )) s"
sed -i "s|$(pwd)|.|g" $OUT/*.log $OUT/*.txt 2>/dev/null
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
