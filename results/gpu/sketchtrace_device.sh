#!/usr/bin/env bash
# Device call for sketchtrace's GPU rate (issue 21; the slowdown placed at 644a026 in
# README.md): the 4K two-sphere and the dist_first renders of raw_final_0996fc7/, 3 times each
# per build, printing render time, Mrays/s, kernel features and verification hash; then, if ncu
# exists, registers per thread, local-memory traffic, achieved occupancy and active threads per
# instruction of dist_first's render kernel (every launch, and over all launches) per build.
#   bash results/gpu/sketchtrace_device.sh NAME=BUILD [NAME=BUILD...]
# Each BUILD (a build directory of some tree, e.g. main's as the in-run baseline, this branch's,
# another commit's from `git archive`) holds miniapps/sketchtrace/sketchtrace built for CUDA;
# every repetition renders each scene with every build in the order given. Run from the root of
# a checkout (inputs/ must hold the scenes). Build only what is needed, e.g.:
#   cmake -S . -B build-cuda "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda \
#     -DCMAKE_CXX_COMPILER=g++ -DRTMINI_ENABLE_TESTS=OFF && cmake --build build-cuda -j 16 \
#     --target sketchtrace
# Outputs (logs, ncu reports) under $OUT (or /tmp/sketchtrace_out). Expected hashes on CUDA:
# 4K 3f0816169ad7e169 for every build; dist_first 18b8a1b1d0ddc23f for builds that sample a
# vertex's lobes in a pass per lobe on the device (0996fc7 to main 23bae46) and
# c599089d83fc4b1b for those with the one-pass lobes (3a56415, branch sketchlobe): nvcc's
# multiply-add contraction differs between the two (miniapps/sketchtrace/README.md).
set -u
[ $# -ge 1 ] || { echo "usage: sketchtrace_device.sh NAME=BUILD [NAME=BUILD...]" >&2; exit 2; }
OUT=${OUT:-/tmp/sketchtrace_out}
mkdir -p "$OUT"
export OMP_PROC_BIND=false
{
  echo "commit $(git rev-parse HEAD 2>/dev/null || echo unknown)"
  date -u
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null
  echo "builds: $*"
} > "$OUT/provenance.txt"

four_k=(inputs/two_spheres/two_spheres.toml --width 3840 --height 2160 --shadow-samples 1024)
dist=(inputs/dist_first/dist_first.toml --width 1000 --height 800 --spp 32)

# render TAG BUILD ARGS...: one timed render; prints time, rate, hash and kernel features.
render() {
  local tag=$1 dir=$2
  shift 2
  timeout 120 "$dir/miniapps/sketchtrace/sketchtrace" "$@" -o "$OUT/$tag.png" > "$OUT/$tag.log" 2>&1
  local rc=$?
  printf '%-22s rc=%d %s | %s | %s\n' "$tag" $rc \
    "$(sed -n 's/^  render: \([0-9.]* s\).*rays, \([0-9.]* Mrays\/s\)/\1, \2/p' "$OUT/$tag.log")" \
    "$(sed -n 's/^  kernel features: \([^ ,]*\).*/\1/p' "$OUT/$tag.log")" \
    "$(tail -n 1 "$OUT/$tag.log" | awk '{print $NF}')"
}

for rep in 1 2 3; do
  for scene in 4k dist; do
    if [ "$scene" = 4k ]; then args=("${four_k[@]}"); else args=("${dist[@]}"); fi
    for pair in "$@"; do render "${pair%%=*}_${scene}_$rep" "${pair#*=}" "${args[@]}"; done
  done
done

# ncu of every render launch of dist_first: its first launch (the ncu figures up to main
# 23bae46) renders the top rows of the image, background only, in under 1 ms; the launches that
# trace the scene take tens of ms. Prints each launch and the totals (time, local sectors) and
# time-weighted means (warps active, threads per instruction) over all of them.
if command -v ncu > /dev/null; then
  metrics=launch__registers_per_thread,launch__occupancy_limit_registers
  metrics+=,sm__warps_active.avg.pct_of_peak_sustained_active
  metrics+=,l1tex__t_sectors_pipe_lsu_mem_local_op_ld.sum,l1tex__t_sectors_pipe_lsu_mem_local_op_st.sum
  metrics+=,smsp__thread_inst_executed_per_inst_executed.ratio,gpu__time_duration.sum
  for pair in "$@"; do
    name=${pair%%=*} dir=${pair#*=}
    timeout 600 ncu --clock-control none --kernel-name-base demangled \
      --kernel-name regex:PixelKernel --metrics "$metrics" --csv --print-units base \
      "$dir/miniapps/sketchtrace/sketchtrace" "${dist[@]}" -o "$OUT/ncu_$name.png" \
      > "$OUT/ncu_dist_$name.csv" 2>&1
    echo "ncu $name rc=$?"
    python3 "$(dirname "$0")/sketchtrace_ncu_summary.py" "$OUT/ncu_dist_$name.csv"
  done
else
  echo "ncu not found: no kernel metrics"
fi
sed -i "s|$(pwd)|.|g" "$OUT"/*.log "$OUT"/*.txt "$OUT"/*.csv 2> /dev/null
rm -f "$OUT"/*.png
