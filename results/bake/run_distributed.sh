#!/bin/bash
# The distributed-map measurements of results/bake/distributed.md (issue 19) on one 16-core host:
#   strong scaling, bunny_room N=300 K=4 .bsb: 1x1 1x16 2x8 4x4 8x2 16x1 (ranks x threads,
#     --map-by slot:PE=t --bind-to core), 4x4 16x1 again with --balance pilot (the cut before
#     the counted recut) and 2x8 4x4 16x1 with --balance spatial; table.md ends with the balance
#     of each run (phases, slowest rank's iteration, max / mean of the counted work);
#   the measured recut (--balance measured) against the counted cut (cost) at 2x8 4x4 8x2 16x1,
#     alternated three times (recut_BALANCE_PxT_I: the host's noise lands on both alike);
#   weak scaling, 1..16 ranks x 1 thread on the two-sheet scene (make_sheets_scene.py) grown
#     with the ranks (side 150 sqrt(P)), N=200 K=3; again with --balance spatial and with
#     --balance measured (2..16 ranks);
#     and P concurrent 1-rank bakes of the 1-rank scene, one per core (busy_P_i): the node as
#     full as a P-rank run (shared L3 and memory bandwidth) without any communication, the
#     baseline that separates the node's saturation from the distributed map's own cost;
#   weak scaling on P closed rooms (make_rooms_scene.py: work per rank constant, every ray in its
#     room), 1..16 ranks x 1 thread, N=200 K=3 as weak (weakrooms_P), the same with --bvh sah
#     (weakroomssah_P: the LBVH's nodes per ray grow more with P), and P concurrent 1-rank
#     bakes of the 1-room scene (busyrooms_P_i);
#   the changed-only exchange (--exchange changed, the default) against the full one, bunny_room
#     N=300 K=4 at 2x8 4x4 16x1, alternated three times (exchange_{full,changed}_PxT_I);
#   strong scaling in one run for the acceptance table (scaling): bunny_room N=300 K=4, 1x1 once,
#     then 1x16 2x8 4x4 8x2 16x1 alternated three times (scaling_PxT_I), default options;
#   one bake that does not fit replicated: 1,008,204 vertices (side 710) at N=1000 K=2 on 16x1;
#   the issue's weak and strong efficiency rows with repeats (acceptance; not part of all).
# Every run writes its summary (verification hash, peak RSS per rank, map statistics) and
# timings (.h5) to OUT_DIR; table.md collects them. Usage (from the repository root, build/ built):
#   results/bake/run_distributed.sh OUT_DIR [strong|scaling|weak|weakrooms|weakshare|exchange|big|acceptance|all]
# BAKE=path runs another build's bake (a baseline in the same call), on the same inputs;
# MPI_ARGS="..." adds mpirun options to every run (e.g. another MPI transport).
set -eu
out=$1
what=${2:-all}
src=$(cd "$(dirname "$0")/../.." && pwd)
bake=${BAKE:-$src/build/miniapps/bake/bake}
gen=$src/build/inputs/rtmini-gen-inputs
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false
{
  echo "commit $(git -C "$src" rev-parse --short=12 HEAD 2>/dev/null || echo unknown)"
  echo "date $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "machine $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)," \
    "$(free -g | awk '/Mem:/{print $2}') GiB"
  echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
} >"$out/provenance.txt"

# run NAME RANKS THREADS ARGS...: one bake, pinned, with its log, summary and timings.
run() {
  local name=$1 np=$2 t=$3
  shift 3
  echo "== $name ($np x $t)" >&2
  OMP_NUM_THREADS=$t /usr/bin/time -f "wall %e s" -o "$out/$name.time" \
    mpirun -n "$np" --map-by "slot:PE=$t" --bind-to core ${MPI_ARGS:-} "$bake" "$@" \
    --summary "$out/$name.json" --timings "$out/$name.h5" >"$out/$name.log" 2>&1 ||
    echo "   $name failed: see $out/$name.log" >&2
}

if [ "$what" = strong ] || [ "$what" = all ]; then
  "$gen" bunny_room --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_room.bs"
  for pt in 1x1 1x16 2x8 4x4 8x2 16x1; do
    run "strong_$pt" "${pt%x*}" "${pt#*x}" "$out/bunny_room.bs" -o "$out/strong.bsb" \
      --viewpoints 300 --iterations 4
  done
  for pt in 4x4 16x1; do  # the pilot's cut: no recount after the mirror trace
    run "pilot_$pt" "${pt%x*}" "${pt#*x}" "$out/bunny_room.bs" -o "$out/strong.bsb" \
      --viewpoints 300 --iterations 4 --balance pilot
  done
  for pt in 2x8 4x4 16x1; do  # the same with spatial (Morton-block) ownership
    run "spatial_$pt" "${pt%x*}" "${pt#*x}" "$out/bunny_room.bs" -o "$out/strong.bsb" \
      --viewpoints 300 --iterations 4 --balance spatial
  done
  for i in 1 2 3; do  # the measured recut against the counted cut, alternated
    for pt in 2x8 4x4 8x2 16x1; do
      for b in cost measured; do
        run "recut_${b}_${pt}_$i" "${pt%x*}" "${pt#*x}" "$out/bunny_room.bs" -o "$out/strong.bsb" \
          --viewpoints 300 --iterations 4 --balance "$b"
      done
    done
  done
  rm -f "$out/strong.bsb"
fi
# busy NAME NP SCENE ARGS...: NP single-rank bakes of SCENE at once, the i-th pinned to core i
# (NAME_NP_i).
busy() {
  local name=$1 np=$2 scene=$3
  shift 3
  echo "== ${name}_$np ($np concurrent 1 x 1)" >&2
  for ((i = 0; i < np; i++)); do
    OMP_NUM_THREADS=1 taskset -c "$i" mpirun -n 1 --bind-to none "$bake" "$scene" \
      -o "$out/${name}_$i.bsb" "$@" --summary "$out/${name}_${np}_$i.json" \
      >"$out/${name}_${np}_$i.log" 2>&1 &
  done
  wait
  rm -f "$out/${name}"_*.bsb
}

if [ "$what" = weak ] || [ "$what" = all ]; then
  python3 "$src/results/bake/make_sheets_scene.py" 150 "$out/sheets_1.bs"
  for np in 2 4 8 16; do
    busy busy "$np" "$out/sheets_1.bs" --viewpoints 200 --iterations 3
  done
  for np in 1 2 4 8 16; do
    side=$(python3 -c "import math; print(round(150 * math.sqrt($np)))")
    python3 "$src/results/bake/make_sheets_scene.py" "$side" "$out/sheets_$np.bs"
    run "weak_$np" "$np" 1 "$out/sheets_$np.bs" -o "$out/weak.bsb" --viewpoints 200 --iterations 3
    if [ "$np" -gt 1 ]; then
      run "weakspatial_$np" "$np" 1 "$out/sheets_$np.bs" -o "$out/weak.bsb" --viewpoints 200 \
        --iterations 3 --balance spatial
      run "weakmeasured_$np" "$np" 1 "$out/sheets_$np.bs" -o "$out/weak.bsb" --viewpoints 200 \
        --iterations 3 --balance measured
    fi
    rm -f "$out/sheets_$np.bs" "$out/weak.bsb"
  done
fi
if [ "$what" = weakrooms ] || [ "$what" = all ]; then
  for np in 1 2 4 8 16; do
    python3 "$src/results/bake/make_rooms_scene.py" "$np" "$out/rooms_$np.bs"
    run "weakrooms_$np" "$np" 1 "$out/rooms_$np.bs" -o "$out/weakrooms.bsb" --viewpoints 200 \
      --iterations 3
    run "weakroomssah_$np" "$np" 1 "$out/rooms_$np.bs" -o "$out/weakrooms.bsb" --viewpoints 200 \
      --iterations 3 --bvh sah
    [ "$np" -gt 1 ] || continue
    rm -f "$out/rooms_$np.bs"
    busy busyrooms "$np" "$out/rooms_1.bs" --viewpoints 200 --iterations 3
  done
  rm -f "$out/rooms_1.bs" "$out/weakrooms.bsb"
fi
if [ "$what" = weakshare ]; then
  # The rooms with and without node sharing (--node-sharing on: one copy of the scene per node,
  # work taken between ranks), alternated per P (at P = 1 and 16 also with the SAH tree), and
  # 16 concurrent 1-room bakes.
  for np in 1 2 4 8 16; do
    python3 "$src/results/bake/make_rooms_scene.py" "$np" "$out/rooms_$np.bs"
    run "weakrooms_$np" "$np" 1 "$out/rooms_$np.bs" -o "$out/weakrooms.bsb" --viewpoints 200 \
      --iterations 3
    run "weakshare_$np" "$np" 1 "$out/rooms_$np.bs" -o "$out/weakrooms.bsb" --viewpoints 200 \
      --iterations 3 --node-sharing on
    if [ "$np" -eq 1 ] || [ "$np" -eq 16 ]; then  # the SAH tree over the building, shared
      run "weaksharesah_$np" "$np" 1 "$out/rooms_$np.bs" -o "$out/weakrooms.bsb" --viewpoints 200 \
        --iterations 3 --node-sharing on --bvh sah
    fi
    [ "$np" -eq 1 ] || rm -f "$out/rooms_$np.bs"
  done
  busy busyrooms 16 "$out/rooms_1.bs" --viewpoints 200 --iterations 3
  rm -f "$out/rooms_1.bs" "$out/weakrooms.bsb"
fi
if [ "$what" = exchange ] || [ "$what" = all ]; then
  "$gen" bunny_room --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_room.bs"
  for i in 1 2 3; do
    for pt in 2x8 4x4 16x1; do
      for ex in full changed; do
        run "exchange_${ex}_${pt}_$i" "${pt%x*}" "${pt#*x}" "$out/bunny_room.bs" \
          -o "$out/strong.bsb" --viewpoints 300 --iterations 4 --exchange "$ex"
      done
    done
  done
  rm -f "$out/strong.bsb"
fi
if [ "$what" = scaling ] || [ "$what" = all ]; then
  "$gen" bunny_room --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_room.bs"
  run scaling_1x1 1 1 "$out/bunny_room.bs" -o "$out/strong.bsb" --viewpoints 300 --iterations 4
  for i in 1 2 3; do
    for pt in 1x16 2x8 4x4 8x2 16x1; do
      run "scaling_${pt}_$i" "${pt%x*}" "${pt#*x}" "$out/bunny_room.bs" -o "$out/strong.bsb" \
        --viewpoints 300 --iterations 4
    done
  done
  rm -f "$out/strong.bsb"
fi
if [ "$what" = acceptance ]; then
  # The issue's two efficiency rows with repeats, since one run of a 1-rank bake moves by up to
  # 35 % within minutes on the lent hosts (distributed.md, eighteenth round): weak scaling, P
  # rooms on P x 1 with --node-sharing on (ACC_BVH, default lbvh) for P = ACC_WEAK_P (default 1
  # and 16), in ACC_ROUNDS (default 3) alternated rounds, then P concurrent 1-room bakes for each
  # P > 1 (the node as full, without communication); strong scaling, bunny_room N=300 K=4, 1 x 1
  # before and after three alternated rounds of 1 x 16 and 16 x 1 (on). acceptance_table.py
  # reads them.
  for np in ${ACC_WEAK_P:-1 16}; do python3 "$src/results/bake/make_rooms_scene.py" "$np" "$out/rooms_$np.bs"; done
  [ -f "$out/rooms_1.bs" ] || python3 "$src/results/bake/make_rooms_scene.py" 1 "$out/rooms_1.bs"
  for ((i = 1; i <= ${ACC_ROUNDS:-3}; i++)); do
    for bvh in ${ACC_BVH:-lbvh}; do
      for np in ${ACC_WEAK_P:-1 16}; do
        run "accweak_${bvh}_${np}_$i" "$np" 1 "$out/rooms_$np.bs" -o "$out/weakrooms.bsb" \
          --viewpoints 200 --iterations 3 --node-sharing on --bvh "$bvh"
      done
    done
  done
  for np in ${ACC_WEAK_P:-1 16}; do
    [ "$np" -eq 1 ] || busy accbusy "$np" "$out/rooms_1.bs" --viewpoints 200 --iterations 3
  done
  rm -f "$out"/rooms_*.bs "$out/weakrooms.bsb"
  "$gen" bunny_room --scene "$src/inputs/meshes/stanford-bunny.obj" -o "$out/bunny_room.bs"
  strong=("$out/bunny_room.bs" -o "$out/strong.bsb" --viewpoints 300 --iterations 4)
  run accstrong_1x1_1 1 1 "${strong[@]}"
  for i in 1 2 3; do
    run "accstrong_1x16_$i" 1 16 "${strong[@]}"
    run "accstrong_16x1_$i" 16 1 "${strong[@]}" --node-sharing on
  done
  run accstrong_1x1_2 1 1 "${strong[@]}"
  rm -f "$out/strong.bsb"
fi
if [ "$what" = big ] || [ "$what" = all ]; then
  python3 "$src/results/bake/make_sheets_scene.py" 710 "$out/sheets_1m.bs"
  run big_16x1 16 1 "$out/sheets_1m.bs" -o "$out/big.bsb" --viewpoints 1000 --iterations 2
  ls -l "$out/big.bsb" >>"$out/big_16x1.log" 2>&1 || true
  rm -f "$out/sheets_1m.bs" "$out/big.bsb"
fi
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/provenance.txt"
python3 "$src/results/bake/distributed_table.py" "$out" >"$out/table.md" && cat "$out/table.md"
