#!/usr/bin/env bash
# Texture filtering (issue 24): what ray-cone mip selection buys on the textured cube's floor,
# seen receding to the horizon (8 x 8 repeats of a 128-texel tile map: several texels per pixel
# beyond a metre). Reference: the finest level (--texture-filter none) at REF_SPP samples per
# pixel, which converges to the pixel's box-filtered texture. Tests: ray cones and level 0 at
# 1, 4 and 16 spp, RMSE against it (sketchtrace --reference) and the process CPU time
# (1 thread). Writes raw_texture_filter/ and texture_filter.csv.
# Usage: results/accuracy/texture_filter.sh [build-dir]   (env: W H REF_SPP)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$root/build}
app=$build/miniapps/sketchtrace/sketchtrace
scene=$root/inputs/textured_cube/textured_cube.toml
out=$root/results/accuracy/raw_texture_filter
W=${W:-160} H=${H:-120} REF_SPP=${REF_SPP:-256}
export OMP_NUM_THREADS=1 OMP_PROC_BIND=false OMP_WAIT_POLICY=passive
mkdir -p "$out"
view=(--camera-pos 0,0.5,0.6 --look-at 0,0,3.2 --width "$W" --height "$H" --shadow-samples 1
      --soft-shadows off)
"$app" "$scene" "${view[@]}" --texture-filter none --spp "$REF_SPP" -o "$out/reference.exr" \
  > "$out/reference.log"
csv=$root/results/accuracy/texture_filter.csv
echo "filter,spp,cpu_s,rmse,psnr_db,ssim" > "$csv"
for spp in 1 4 16; do
  for filter in cone none; do
    id=${filter}_spp$spp
    echo "$app $scene ${view[*]} --texture-filter $filter --spp $spp" > "$out/$id.log"
    TIMEFORMAT="cpu %U %S"
    { time "$app" "$scene" "${view[@]}" --texture-filter "$filter" --spp "$spp" \
      --reference "$out/reference.exr" -o "$out/$id.png" >> "$out/$id.log" 2>&1; } 2>> "$out/$id.log"
    cpu=$(awk '/^cpu / {print $2 + $3}' "$out/$id.log")
    rmse=$(sed -n 's/.*RMSE \([0-9.e+-]*\),.*/\1/p' "$out/$id.log")
    psnr=$(sed -n 's/.*PSNR \([0-9.inf-]*\) dB.*/\1/p' "$out/$id.log")
    ssim=$(sed -n 's/.*SSIM \([0-9.]*\) .*/\1/p' "$out/$id.log")
    echo "$filter,$spp,$cpu,$rmse,$psnr,$ssim" >> "$csv"
  done
done
cat "$csv"
