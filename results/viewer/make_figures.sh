#!/bin/bash
# Regenerates the viewer figures of results/viewer: bakes the Cornell boxes and the bunny room
# to .bsb, renders each map with the web viewer (headless chromium) and with `bake render` for
# the same cameras, and records their agreement (agreement.jsonl). See README.md here.
#   results/viewer/make_figures.sh BUILD_DIR OUT_DIR
# Needs: ninja -C BUILD_DIR bake rtmini-input-bunny; npm ci --prefix miniapps/bake/viewer.
set -euo pipefail
build=$(realpath "$1")
out=$(realpath -m "$2")
root=$(realpath "$(dirname "$0")/../..")
bake=$build/miniapps/bake/bake
viewer=$root/miniapps/bake/viewer
maps=$(mktemp -d)
trap 'rm -rf "$maps"' EXIT
mkdir -p "$out"
export OMP_NUM_THREADS=2
: >"$out/agreement.jsonl"

bake_map() {  # bake_map SCENE NAME N K: the map, its bake summary, its last stdout line
  "$bake" "$1" --viewpoints "$3" --iterations "$4" -o "$maps/$2.bsb" \
    --summary "$out/$2_bake.json" | tail -n 1
  echo "$2.bsb: $(stat -c %s "$maps/$2.bsb") bytes"
}

compare() {  # compare NAME MAP EYE TARGET FOV: both images and one line of agreement.jsonl
  node "$viewer/tests/compare_render.mjs" --bake "$bake" --map "$maps/$2.bsb" --out "$out" \
    --name "$1" --eye "$3" --target "$4" --fov "$5" --size 512x512 >>"$out/agreement.jsonl"
  tail -n 1 "$out/agreement.jsonl"
}

bake_map "$root/inputs/cornell/cornell_box.bs" cornell_box_n100_k2 100 2
compare cornell_box_front cornell_box_n100_k2 0,1,3.9 0,1,0 45
compare cornell_box_boxes cornell_box_n100_k2 0.9,1.1,2.4 -0.1,0.7,-0.2 45

bake_map "$root/inputs/cornell_big/cornell_big_raw.bs" cornell_big_n100_k2 100 2
compare cornell_big_side cornell_big_n100_k2 2.2,1.6,3.6 0,0.9,0 45

bake_map "$build/inputs/bunny/bunny_room.bs" bunny_room_n100_k2 100 2
compare bunny_front bunny_room_n100_k2 0.12,0.2,0.45 -0.017,0.1,0 40
compare bunny_side bunny_room_n100_k2 -0.3,0.24,0.3 -0.017,0.12,0 45

# The vertex-grid view of the bunny (the paper's figure 4.e view), viewer only.
node "$viewer/tests/screenshot.mjs" "$maps/bunny_room_n100_k2.bsb" "$out/bunny_front_grid.png" \
  'eye=0.12,0.2,0.45&target=-0.017,0.1,0&fov=40&w=512&h=512&grid=1'
