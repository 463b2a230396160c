#!/bin/bash
# Measures the issue-18 figures of results/accuracy/extremes.md that are not stability cases:
# the cube furnace with smoothing on (creases), AO of identical instances (per-instance ray
# keys), AO under a coaxial disk at the default -d, a small receiver beside a large blocker.
# Usage: results/accuracy/extremes_issue_figures.sh BUILD_DIR TAG EXRSTATS
#   EXRSTATS: a program printing mean / standard error / median of an EXR's luminance (the
#   committed figures used a 30-line throwaway linked against rtmini_host's read_image)
#   writes results/accuracy/raw_extremes/TAG/issue_figures.log
set -u
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=$1
tag=$2
exrstats=$3
sketch=$build/miniapps/sketchtrace/sketchtrace
bake=$build/miniapps/bake/bake
out=$root/results/accuracy/raw_extremes/$tag
mkdir -p "$out"
work=$(mktemp -d)
export OMP_NUM_THREADS=2 OMP_PROC_BIND=false
cd "$work" || exit 1
{
  echo "# $(date -u +%FT%TZ) binaries of $(git -C "$build" rev-parse --short HEAD) $(hostname) $(nproc) cores (shared)"
  echo "# SKETCH=$sketch BAKE=$bake"

  echo "## cube furnace: closed diffuse cube (8 shared corners), E = 1, albedo 0.5, direct light"
  echo "## only, smoothing on, crease 60 deg; exact 1.5 everywhere. 64x64, 16 spp, 64 shadow"
  echo "## samples; 'centre' = pixels within 6 px of the image centre (middle of the far wall)."
  printf 'newmtl furnace\nKd 0.5 0.5 0.5\nKe 1 1 1\n' >cube.mtl
  {
    echo "mtllib cube.mtl"
    for v in "-1 -1 -1" "1 -1 -1" "1 1 -1" "-1 1 -1" "-1 -1 1" "1 -1 1" "1 1 1" "-1 1 1"; do echo "v $v"; done
    echo "usemtl furnace"
    printf 'f 1 2 3 4\nf 8 7 6 5\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n'
  } >cube.obj
  printf '[camera]\nposition = [0.0, 0.0, 0.9]\nlook_at = [0.0, 0.0, -1.0]\nfov_deg = 110.0\n\n[[meshes]]\nfile = "cube.obj"\n' >cube.toml
  for seed in 1 11 12 13; do
    for smooth in on off; do
      "$sketch" cube.toml --width 64 --height 64 --spp 16 --shadow-samples 64 --bounces 0 \
        --indirect off --edge-thickness 0 --smooth $smooth --seed $seed -o cube.exr >/dev/null 2>&1 ||
        echo "sketchtrace failed"
      echo "seed $seed smooth $smooth:"
      "$exrstats" cube.exr 6
    done
  done

  echo "## identical instances: spot.obj, -i 3 (three copies on a grid 1.25 extents apart), 64"
  echo "## rays, -m 0.2 (the copies are out of each other's reach: identical occluders); fraction"
  echo "## of vertices whose AO is bit-identical in all three copies"
  "$bake" ao "$root/inputs/meshes/spot.obj" -i 3 -r 64 -m 0.2 --ply-ascii -o spot3.ply >spot3.log 2>&1 ||
    echo "bake ao failed: $(tail -n 1 spot3.log)"
  grep -E "^Mean AO|mean_ao" spot3.log
  awk 'NF == 7 && !/^[a-z]/ { v[n++] = $7 } END {
    m = n / 3; same = 0; for (i = 0; i < m; i++) if (v[i] == v[i + m] && v[i] == v[i + 2 * m]) same++;
    printf "vertices per copy %d, identical in all 3 copies: %d (%.1f %%)\n", m, same, 100 * same / m }' spot3.ply

  echo "## coaxial disk at the default -d: receiver 0.02 x 0.02 (3x3 vertices) at the origin"
  echo "## under a disk of radius 1 at height 0.5 (a blocker); exact visibility 0.2 at the centre"
  echo "## (0.19995 averaged over the receiver); 4096 samples x 1024 rays, no ground plane"
  {
    for j in 0 1 2; do for i in 0 1 2; do echo "v $(awk -v i=$i 'BEGIN{print (i-1)*0.01}') 0 $(awk -v j=$j 'BEGIN{print (j-1)*0.01}')"; done; done
    echo "f 1 4 5 2"; echo "f 2 5 6 3"; echo "f 4 7 8 5"; echo "f 5 8 9 6"
  } >rx.obj
  {
    echo "v 0 0.5 0"
    awk 'BEGIN { for (i = 0; i < 128; i++) { a = 2 * 3.14159265358979 * i / 128; print "v", cos(a), 0.5, sin(a) } }'
    for i in $(seq 2 129); do j=$((i == 129 ? 2 : i + 1)); echo "f 1 $i $j"; done
  } >disk.obj
  printf '[settings]\nblockers = [1]\n\n[[meshes]]\nfile = "rx.obj"\n\n[[meshes]]\nfile = "disk.obj"\n' >disk.toml
  "$bake" ao disk.toml -r 1024 -s 4096 --no-ground-plane -o disk.ply >disk.log 2>&1 ||
    echo "bake ao failed: $(tail -n 1 disk.log)"
  grep -E "ray offset|^Mean AO" disk.log

  echo "## small receiver beside a large blocker: receiver 0.01 x 0.01 on the floor 0.001 from a"
  echo "## 1000-unit wall (a blocker), no ground plane; exact 0.5 (half the hemisphere is wall)"
  printf 'v 0.001 0 -0.005\nv 0.011 0 -0.005\nv 0.011 0 0.005\nv 0.001 0 0.005\nf 1 4 3 2\n' >small.obj
  printf 'v 0 0 -500\nv 0 0 500\nv 0 1000 500\nv 0 1000 -500\nf 1 2 3 4\n' >wall.obj
  printf '[settings]\nblockers = [1]\n\n[[meshes]]\nfile = "small.obj"\n\n[[meshes]]\nfile = "wall.obj"\n' >wall.toml
  "$bake" ao wall.toml -r 1024 -s 4096 --no-ground-plane -o wall.ply >wall.log 2>&1 ||
    echo "bake ao failed: $(tail -n 1 wall.log)"
  grep -E "ray offset|^Mean AO" wall.log
} >"$out/issue_figures.log" 2>&1
cat "$out/issue_figures.log"
rm -rf "$work"
