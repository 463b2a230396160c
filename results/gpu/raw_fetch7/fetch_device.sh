#!/usr/bin/env bash
# Historical copy: the device command of the fetch-kernel measurement (2026-11-24 22:04 UTC), run
# from a trial merge of main 117e006, gpu7 da8a8ae and bake7 c2f055d through device_command.sh
# beside it. The fetch kernels were taken out of the tree after that measurement (results/gpu/README.md);
# check out 6524973 to run it again.
# One device call for issue 21's dynamic ray fetch (branch gpu7): CUDA build of rtmini-bvh-bench,
# then results/gpu/anyhit_device.sh on the kernels with dynamic ray fetch (fetch, fetch8,
# speculative_fetch, fetch_late, fetch_block) beside the one-ray-per-thread kernels they build
# on (stored, speculative) and today's default, AO on dragon and bunny, SAH and LBVH, two passes
# (forward, then reversed; the best and worst run of each kept), then ncu of each on dragon AO
# SAH.
#
# Usage, from the root of a checkout of the branch on the device machine, with Kokkos CUDA
# installed (KOKKOS_CUDA, default /opt/kokkos-cuda; the coordinator's .carry/dev_env.sh, if
# present, defines deps_flags and PATH):
#   bash results/gpu/fetch_device.sh [measure|unit]
#     measure (default): build the bench into build-cuda, bench and ncu (about 7.5 min: build
#                        ~2-3 min, 64 bench runs of ~3 s, 8 ncu runs of ~10 s)
#     unit:              build and run unit.core.cuda (the AnyHitKernels* oracle tests of every
#                        kernel against brute force, the fetch drivers' coverage test)
# Outputs under $OUT (default /tmp/fetch_out): provenance.txt, cfg.log, build.log, and
# anyhit_device.sh's bench.txt, summary.txt, ncu_*.csv, ncu_summary.txt (or unit_core_cuda.txt).
# Expected: every kernel gives the default's verification hash (dragon AO 65f36ebef7cd2ba5,
# bunny AO 7aba1e15a4309959).
set -u
phase=${1:-measure}
[ -f .carry/dev_env.sh ] && source .carry/dev_env.sh
[ -n "${deps_flags+x}" ] || deps_flags=()
export OUT=${OUT:-/tmp/fetch_out}
mkdir -p "$OUT"
B=${BUILD_DIR:-build-cuda}
t0=$(date +%s)
target=rtmini-bvh-bench
[ "$phase" = unit ] && target=rtmini_unit_core_cuda
cmake -S . -B "$B" "${deps_flags[@]}" -DKokkos_ROOT="${KOKKOS_CUDA:-/opt/kokkos-cuda}" \
  -DCMAKE_CXX_COMPILER=g++ -DCMAKE_BUILD_TYPE=Release > "$OUT/cfg.log" 2>&1 ||
  { tail -30 "$OUT/cfg.log"; exit 3; }
cmake --build "$B" -j "${JOBS:-16}" --target $target > "$OUT/build.log" 2>&1
rc=$?
echo "build $target rc=$rc $(($(date +%s) - t0)) s"
[ $rc = 0 ] || { grep -E 'error' -A3 "$OUT/build.log" | head -40; exit 3; }
if [ "$phase" = unit ]; then
  (cd "$B" && timeout 400 ctest -R 'unit.core.cuda' --output-on-failure --timeout 390 \
    > "$OUT/unit_core_cuda.txt" 2>&1)
  echo "unit.core.cuda rc=$? $(($(date +%s) - t0)) s"
  tail -5 "$OUT/unit_core_cuda.txt"
  exit 0
fi
# A smoke run of each kernel on the small Cornell box first: one that fails or does not finish
# in 20 s (a hang) is left out of the measured list, so it cannot eat the call's time.
kernels=""
for k in default stored speculative fetch fetch8 speculative_fetch fetch_late fetch_block; do
  if timeout 20 "$B/bench/rtmini-bvh-bench" inputs/meshes/CornellBox-Original.obj --workload ao \
    --quality lbvh --gpu-trace $k --repeats 1 > "$OUT/smoke_$k.txt" 2>&1; then
    kernels="$kernels $k"
    echo "smoke $k: $(grep '^FOM' "$OUT/smoke_$k.txt")"
  else
    echo "smoke $k FAILED rc=$? (left out; $OUT/smoke_$k.txt)"
  fi
done
KERNELS="$kernels" PASSES=2 RUN_LIMIT=30 bash results/gpu/anyhit_device.sh "$B" all
echo "fetch_device total $(($(date +%s) - t0)) s"
