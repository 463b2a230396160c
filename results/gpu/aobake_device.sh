#!/usr/bin/env bash
# Device call (issue 21, AO whole bake <= 0.15 s): CUDA builds of the baseline (main) and of the
# aobake branch, then the whole bake of dragon x4 (1.25M samples x 64 rays, CG fit on the GPU)
# five times each, baseline, branch and branch with a one-thread OBJ reader alternated, with
# every phase line and the verification hash; the .glb outputs must be byte-identical.
#
# Run from the root of the device copy (main, with .carry/ as for the other device calls) with the
# branch's tree copied next to it, e.g. on this side:
#   git worktree add .aobakewt aobake   (or: mkdir .aobakewt; git archive aobake | tar -x -C .aobakewt)
#   git -C .aobakewt rev-parse HEAD > .aobakewt/.commit; git rev-parse HEAD > .aobakewt/.base_commit
# then on the device:  bash .aobakewt/results/gpu/aobake_device.sh      (outputs in $OUT)
# BASE=<dir> and NEW=<dir> choose other trees (defaults: . and .aobakewt).
set -u
# shellcheck source=/dev/null  # carried by the device call, not in the repository
source .carry/dev_env.sh
export OMP_PROC_BIND=false
BASE=${BASE:-.}
NEW=${NEW:-.aobakewt}
R=$OUT/aobake
mkdir -p "$R" /tmp/aob
t0=$(date +%s)
{
  echo "branch aobake commit $(cat "$NEW/.commit" 2>/dev/null || echo unknown)"
  echo "baseline main commit $(cat "$NEW/.base_commit" 2>/dev/null || cat .carry/commit.txt 2>/dev/null || echo unknown)"
  date -u
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
  nproc
} > "$R/provenance.txt"
# deps_flags comes from dev_env.sh.
# shellcheck disable=SC2154
cfg() { cmake -S "$1" -B "$2" "${deps_flags[@]}" -DKokkos_ROOT=/opt/kokkos-cuda -DCMAKE_CXX_COMPILER=g++ > "$R/cfg_$3.log" 2>&1; }
(cfg "$BASE" "$BASE/build-aob-base" base && cmake --build "$BASE/build-aob-base" -j 8 --target bake > "$R/build_base.log" 2>&1
 echo "base build rc=$? $(( $(date +%s) - t0 )) s") &
(cfg "$NEW" "$NEW/build-aob-new" new && cmake --build "$NEW/build-aob-new" -j 8 --target bake > "$R/build_new.log" 2>&1
 echo "new build rc=$? $(( $(date +%s) - t0 )) s") &
wait
grep -h ' error' "$R/build_base.log" "$R/build_new.log" | head -20
# The same input file for both (the branch does not change inputs/).
# "serial" is the branch with its OBJ reader on one thread (RTMINI_OBJ_THREADS=1): the effect of
# reading the OBJ in pieces on the node's cores.
for rep in 1 2 3 4 5; do
  for t in base new serial; do
    bin=$BASE/build-aob-base/miniapps/bake/bake; [ "$t" != base ] && bin=$NEW/build-aob-new/miniapps/bake/bake
    threads=; [ "$t" = serial ] && threads=1
    log=$R/ao_${t}_$rep.log
    RTMINI_OBJ_THREADS=$threads timeout 60 "$bin" ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg -o /tmp/aob/dragon_$t.glb \
      --summary "$R/ao_${t}_$rep.json" > "$log" 2>&1
    echo "== $t rep $rep rc=$?"
    grep -E '\.\.\. |verification' "$log"
  done
done
cmp /tmp/aob/dragon_base.glb /tmp/aob/dragon_new.glb && cmp /tmp/aob/dragon_base.glb /tmp/aob/dragon_serial.glb &&
  echo "glb outputs identical"
# Median per phase (ms) over the five runs of each binary.
python3 "$NEW/results/ao/phase_medians.py" "$R"
echo "total $(( $(date +%s) - t0 )) s"
