#!/usr/bin/env bash
# Host (OpenMP) render times of several sketchtrace binaries, alternated: for each repetition
# and scene, every binary in the order given. Scenes: the device script's two
# (results/gpu/sketchtrace_device.sh) at host sizes. One line per run: name, scene, repetition,
# render seconds, Mrays/s, verification hash.
#   bash results/gpu/raw_sketchlean/host_alternation.sh REPS "two dist" NAME=BINARY...
set -u
reps=$1 scenes=$2
shift 2
export OMP_PROC_BIND=false
two=(inputs/two_spheres/two_spheres.toml --width 160 --height 90 --shadow-samples 1024)
dist=(inputs/dist_first/dist_first.toml --width 200 --height 160 --spp 32)
for rep in $(seq "$reps"); do
  for scene in $scenes; do
    if [ "$scene" = two ]; then args=("${two[@]}"); else args=("${dist[@]}"); fi
    for pair in "$@"; do
      out=$("${pair#*=}" "${args[@]}" -o /tmp/host_alt_$$.png 2>&1)
      echo "${pair%%=*} $scene $rep $(echo "$out" |
        sed -n 's/^  render: \([0-9.]*\) s.* \([0-9.]*\) Mrays\/s/\1 \2/p') $(echo "$out" |
        tail -n 1 | awk '{print $NF}')"
    done
  done
done
rm -f /tmp/host_alt_$$.png
