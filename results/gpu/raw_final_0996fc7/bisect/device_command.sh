# Device call: sketchtrace's GPU ray rate at two earlier commits (before / after issue 24's merges),
# to place the drop between 2168a2b (7.19 Grays/s 4K, 677 Mrays/s dist_first) and main 0996fc7.
source .carry/dev_env.sh
t0=$(date +%s)
for c in 2789b75 644a026; do
  (mkdir -p /tmp/s_$c && tar -xzf .carry/src_$c.tgz -C /tmp/s_$c && ln -sfn $PWD/inputs/meshes /tmp/s_$c/inputs/meshes && cd /tmp/s_$c &&
   cmake -S . -B b "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF > $OUT/cfg_$c.log 2>&1 &&
   cmake --build b -j 8 --target sketchtrace > $OUT/build_$c.log 2>&1; echo "build $c rc=$? $(( $(date +%s)-t0 )) s") &
done; wait
for c in 2789b75 644a026; do
  S=/tmp/s_$c/b/miniapps/sketchtrace/sketchtrace
  (cd /tmp/s_$c && for rep in 1 2; do
    timeout 60 $S inputs/dist_first/dist_first.toml --width 1000 --height 800 --spp 32 -o /tmp/d.png > $OUT/st_dist_${c}_$rep.log 2>&1
    timeout 60 $S inputs/two_spheres/two_spheres.toml --width 3840 --height 2160 --shadow-samples 1024 -o /tmp/4k.png > $OUT/st_4k_${c}_$rep.log 2>&1
  done)
  for f in $OUT/st_*_${c}_*.log; do echo "$(basename $f): $(grep -E 'render:|verification' $f | tr -s ' ' | tr '\n' '|')"; done
done
echo "total $(( $(date +%s)-t0 )) s"
(cd $OUT && tar czf /tmp/all.tgz . && rm -rf ./* && mv /tmp/all.tgz $OUT/all.tgz)
