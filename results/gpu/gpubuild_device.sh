#!/usr/bin/env bash
# Device commands for branch gpubuild (issue 21, builders): one-pass LBVH, PLOC, --bvh auto.
# Run from the root of a device copy whose CUDA build of this branch is in $1 (default
# build-cuda), e.g. after the recipe of docs/cuda.md:
#   cmake --build build-cuda --target rtmini-bvh-bench rtmini_unit_core_cuda bake
#   bash results/gpu/gpubuild_device.sh build-cuda > $OUT/gpubuild.txt 2>&1
# Prints: the CUDA oracle tests (LBVH, PLOC, SAH against brute force), then per mesh the LBVH and
# PLOC phase times, every builder's build time and SAH cost (vs the host SAH build), and AO traces
# with each builder (verification hashes must agree across builders on one mesh).
set -u
B=${1:-build-cuda}
bench() { echo "== rtmini-bvh-bench $*"; timeout 300 "$B/bench/rtmini-bvh-bench" "$@"; echo "rc=$?"; }
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
git log -1 --format='commit %H %cd' 2>/dev/null
(cd "$B" && timeout 300 ctest -R 'unit.core.cuda' --output-on-failure --timeout 290 | tail -5)
# Builds: phases (each fenced), best-of-10 build times, SAH cost of each builder; AO with each.
for m in inputs/meshes/dragon.obj inputs/meshes/stanford-bunny.obj inputs/meshes/teapot.obj \
         inputs/meshes/cow.obj inputs/meshes/spot.obj inputs/meshes/CornellBox-Original.obj; do
  bench "$m" --build-phases --repeats 10 --samples-per-face 1 --rays 1
  for q in lbvh ploc sah auto; do
    bench "$m" --workload ao --quality "$q" --repeats 5 --time-builds "$q" 2>&1 |
      grep -E '^==|auto:|build:|per ray|rays .*Mrays|FOM|rc='
  done
done
# 1.31M (icosphere:8) and 10M triangles (100 dragons): no host SAH build at 10M (seconds).
bench icosphere:8 --build-phases --repeats 10 --samples-per-face 1 --rays 1
bench inputs/meshes/dragon.obj --copies 10 --build-phases --repeats 10 --samples-per-face 1 --rays 1
bench inputs/meshes/dragon.obj --copies 100 --build-phases --repeats 5 --time-builds lbvh,ploc \
  --samples-per-face 1 --rays 1
for q in lbvh ploc; do
  bench inputs/meshes/dragon.obj --copies 10 --workload ao --quality $q --repeats 3 \
    --time-builds $q
  bench inputs/meshes/dragon.obj --copies 100 --workload ao --quality $q --repeats 3 \
    --time-builds $q --samples-per-face 1 --rays 16
done
bench inputs/meshes/dragon.obj --copies 10 --workload ao --quality sah --repeats 3 --time-builds sah
# The AO whole bake with each build (dragon x4; bake's --bvh auto is its default).
for q in auto lbvh ploc sah; do
  echo "== bake ao --bvh $q"
  timeout 120 "$B/miniapps/bake/bake" ao inputs/ao/dragon_x4.toml -s 1250000 --bvh "$q" \
    -o /tmp/gpubuild_ao.glb 2>&1 | grep -E 'bvh|rays|hash|whole|build' | head -8
done
