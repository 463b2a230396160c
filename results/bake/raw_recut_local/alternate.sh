#!/bin/bash
# Local (2-core, shared) alternation of --balance cost and --balance measured on bunny_room,
# N=300 K=4, 2 ranks x 1 thread. Usage: alternate.sh OUT REPS (from the repository root, build/ built).
set -eu
out=$1
reps=${2:-4}
mkdir -p "$out"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_PROC_BIND=false OMP_NUM_THREADS=1
[ -e "$out/bunny_room.bs" ] ||
  build/inputs/rtmini-gen-inputs bunny_room --scene inputs/meshes/stanford-bunny.obj -o "$out/bunny_room.bs"
for i in $(seq 1 "$reps"); do
  for b in cost measured; do
    echo "load $(cut -d' ' -f1-3 /proc/loadavg) before recut_${b}_2x1_$i" >>"$out/load.txt"
    nice mpirun -n 2 --bind-to none build/miniapps/bake/bake "$out/bunny_room.bs" -o "$out/o.bsb" \
      --viewpoints 300 --iterations 4 --balance "$b" --summary "$out/recut_${b}_2x1_$i.json" \
      --timings "$out/recut_${b}_2x1_$i.h5" >"$out/recut_${b}_2x1_$i.log" 2>&1
  done
done
rm -f "$out/o.bsb"
