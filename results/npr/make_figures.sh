#!/usr/bin/env bash
# Recreates results/npr from the two seed scenes (run from the repository root after
# bash jobs/local/build.sh). BEFORE names a sketchtrace-post built from main at 7de0f94
# (the state before issue 23) for the *_before.png column; leave it empty to skip it.
set -euo pipefail
out=results/npr
work=${WORK:-/tmp/npr_fig}
sketch=build/miniapps/sketchtrace/sketchtrace
post=build/miniapps/sketchtrace/sketchtrace-post
mkdir -p "$work"
export OMP_PROC_BIND=false
for scene in two_spheres watchtower; do
  OMP_NUM_THREADS=2 "$sketch" "inputs/$scene/$scene.toml" --width 640 --height 480 --spp 4 \
    --aov depth,normal,object,cost,edge --style none -o "$work/$scene.exr" > "$work/$scene.log"
  export OMP_NUM_THREADS=1
  "$post" "$work/$scene.exr" -o "$out/${scene}_render.png" --passes paper --style none \
    --paper-strength 0 > /dev/null
  for style in sketch color_pencil; do
    "$post" "$work/$scene.exr" -o "$out/${scene}_$style.png" --style $style --stats \
      --summary "$out/${scene}_$style.json" | grep '^stats'
  done
  if [[ -n ${BEFORE:-} ]]; then
    "$BEFORE" "$work/$scene.exr" -o "$out/${scene}_before.png" > /dev/null
  fi
done
"$post" "$work/two_spheres.exr" -o "$work/unused.png" --dump-bitmaps "$out/tam_level" \
  --summary "$out/tam_levels.json" > /dev/null
for f in tests/reference/npr/*.png; do cp "$f" "$out/synthetic_$(basename "$f")"; done
"${PYTHON:-/usr/bin/python3}" "$out/compare.py" "$out" "$out/compare.png"
