#!/usr/bin/env bash
# Assembles the fuzz targets' seed corpora (nothing large is committed): the bundled inputs
# and the known-bad files of tests/, and small files written by this build's apps (.bsb,
# checkpoints, cost map, PNG, PPM). One folder per target under OUT.
# Usage: make_seeds.sh OUT     Env: SOURCE (repository root), BAKE, SKETCH (binaries)
set -euo pipefail
out=$1
rm -rf "$out"
for t in obj bs bsb scene_toml ao_scene ao_options bake_checkpoint sketch_checkpoint cost_map ppm png gltf; do
  mkdir -p "$out/$t"
done
inputs=$SOURCE/inputs
bad=$SOURCE/tests/data/bad
small=16384  # bytes; larger inputs only slow the fuzzer down

# seed TARGET FILE: FILE as a seed when it is small, else its first 100 lines.
seed() {
  local dst
  dst=$out/$1/$(basename "$(dirname "$2")")_$(basename "$2")
  if (($(stat -c %s "$2") <= small)); then cp "$2" "$dst"; else head -n 100 "$2" >"$dst"; fi
}

# OBJ: its library is appended after a "#%mtl" line and renamed m.mtl (fuzz_obj.cpp).
for f in "$inputs"/*/*.obj "$bad"/*.obj; do
  seed obj "$f"
  dst=$out/obj/$(basename "$(dirname "$f")")_$(basename "$f")
  lib=$(sed -n 's/^mtllib[[:space:]]\+//p' "$f" | head -n 1 | tr -d '\r')
  if [[ -n $lib ]]; then
    sed -i 's/^mtllib[[:space:]].*/mtllib m.mtl/' "$dst"
    if [[ -f $(dirname "$f")/$lib ]]; then
      printf '\n#%%mtl\n' >>"$dst"
      cat "$(dirname "$f")/$lib" >>"$dst"
    fi
  fi
done
for f in "$inputs"/*/*.bs "$bad"/*.bs; do seed bs "$f"; done
# glTF: the malformed test file (data: URI buffer), a valid variant of it (one vertex), and
# below, the .glb bake --mode ao writes.
seed gltf "$SOURCE/tests/regression/ao/bad_gltf.gltf"
sed 's/"count": 3/"count": 1/' "$SOURCE/tests/regression/ao/bad_gltf.gltf" >"$out/gltf/one_vertex.gltf"
for f in "$bad"/ppm_*.ppm; do seed ppm "$f"; done
for f in "$bad"/png_*.png; do seed png "$f"; done
# HDF5 files that once showed a problem (tests/data/bad/h5_*.h5) go to every HDF5 reader.
for f in "$bad"/h5_*.h5; do
  for t in bake_checkpoint sketch_checkpoint cost_map; do seed $t "$f"; done
done

# TOML scenes: every mesh becomes the triangle the targets write (m.obj, or m.bs for .bs).
for f in "$inputs"/*/*.toml "$bad"/*.toml "$SOURCE"/tests/regression/sketchtrace/bad/*.toml; do
  for t in scene_toml ao_scene; do
    seed $t "$f"
    dst=$out/$t/$(basename "$(dirname "$f")")_$(basename "$f")
    sed -i -e 's/^\([[:space:]]*file[[:space:]]*=[[:space:]]*\)"[^"]*\.bs"/\1"m.bs"/' \
           -e 's/^\([[:space:]]*file[[:space:]]*=[[:space:]]*\)"[^"]*\.obj"/\1"m.obj"/' "$dst"
  done
done

# bake ao command lines, one argument per line.
printf 'm.obj\n' >"$out/ao_options/plain"
printf 'm.obj\n-o\nao.ply\n-r\n16\n-s\n1000\n-t\n2\n--seed\n7\n--bvh\nsah\n' >"$out/ao_options/counts"
printf 'm.toml\n-g\n2\n50\n0.1\n-d\n0.02\n-m\n5\n-w\n0.5\n--passes\n4\n' >"$out/ao_options/ground"
printf 'm.bs\n--no-ground-plane\n--no_least_squares\n--batch\n100\n-i\n3\n--ply-ascii\n' \
  >"$out/ao_options/flags"

# Command lines that once showed a problem (tests/data/bad/ao_options_*.args).
cp "$bad"/ao_options_*.args "$out/ao_options/"

# Small outputs of this build's apps.
work=$out/.work
mkdir -p "$work"
cube=$inputs/cube/cube.bs
scene=$inputs/two_spheres/two_spheres.toml
tiny=(--width 8 --height 6 --spp 1 --shadow-samples 1)
(
  cd "$work"
  export OMP_NUM_THREADS=1 OMP_PROC_BIND=false
  "$BAKE" "$cube" --viewpoints 4 -o cube.bsb >/dev/null
  "$BAKE" "$inputs/cornell/cornell_box.bs" --viewpoints 2 -o cornell.bsb >/dev/null
  "$BAKE" --mode ao "$cube" --rays 4 -o cube.glb >/dev/null
  rc=0
  "$BAKE" "$cube" --viewpoints 4 --iterations 3 --checkpoint bake.h5 --stop-after-iteration 1 \
    >/dev/null 2>&1 || rc=$?
  [[ $rc == 4 ]] || { echo "make_seeds: bake --checkpoint gave exit $rc" >&2; exit 1; }
  rc=0
  "$SKETCH" "$scene" "${tiny[@]}" --chunk-pixels 16 --checkpoint sketch.h5 --stop-after-chunks 1 \
    >/dev/null 2>&1 || rc=$?
  [[ $rc == 4 ]] || { echo "make_seeds: sketchtrace --checkpoint gave exit $rc" >&2; exit 1; }
  "$SKETCH" "$scene" "${tiny[@]}" --balance metric --cost-map cost.h5 -o rgb.png >/dev/null
  "$SKETCH" "$scene" "${tiny[@]}" -o rgb.ppm >/dev/null
)
cp "$work"/*.bsb "$out/bsb/"
cp "$work/bake.h5" "$out/bake_checkpoint/"
cp "$work/sketch.h5" "$out/sketch_checkpoint/"
cp "$work/cost.h5" "$out/cost_map/"
cp "$work/rgb.png" "$out/png/"
cp "$work/rgb.ppm" "$out/ppm/"
cp "$work/cube.glb" "$out/gltf/"
rm -rf "$work"
for t in "$out"/*/; do echo "seeds: $(basename "$t") $(find "$t" -type f | wc -l)"; done
