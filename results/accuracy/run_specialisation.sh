#!/bin/bash
# Kernel specialisation speed-up (issue 7): each bundled scene rendered with the kernel
# specialised on its features and with --general-kernel, REPS times each, interleaved.
# Besides the render phase's wall time it records the process's CPU time (user + sys from
# /usr/bin/time), which a shared, loaded machine disturbs far less; run it with
# OMP_NUM_THREADS=1 so CPU time is render work. A 1x1 run per case gives the setup cost.
# Prints one CSV line per run: scene,extra,kernel,features,pixels,render_s,cpu_s,hash.
# Usage: run_specialisation.sh SKETCHTRACE INPUTS [REPS [WIDTH HEIGHT]]
set -euo pipefail
sketch=$1
inputs=$2
reps=${3:-5}
width=${4:-480}
height=${5:-360}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "scene,extra,kernel,features,pixels,render_s,cpu_s,hash"
run() {  # run SCENE KERNEL WIDTH HEIGHT EXTRA...
  local scene=$1 kernel=$2 w=$3 h=$4
  shift 4
  local flags=()
  [[ $kernel == general ]] && flags=(--general-kernel)
  /usr/bin/time -f "%U %S" -o "$tmp/time" "$sketch" "$inputs/$scene/$scene.toml" --width "$w" \
    --height "$h" "$@" "${flags[@]}" >"$tmp/out"
  local features seconds hash cpu
  features=$(sed -n 's/^  kernel features: \([^ ,]*\).*/\1/p' "$tmp/out")
  seconds=$(sed -n 's/^  render: \([0-9.]*\) s.*/\1/p' "$tmp/out")
  hash=$(tail -n 1 "$tmp/out" | awk '{print $NF}')
  cpu=$(awk '{printf "%.2f", $1 + $2}' "$tmp/time")
  echo "$scene,${*:-default},$kernel,$features,$((w * h)),$seconds,$cpu,$hash"
}
for case in "two_spheres" "spheres" "watchtower" "dist_first" "two_spheres --bounces 0" \
  "spheres --bounces 0"; do
  read -r -a words <<<"$case"
  run "${words[0]}" specialised 1 1 "${words[@]:1}"
  for ((i = 0; i < reps; i++)); do
    run "${words[0]}" specialised "$width" "$height" "${words[@]:1}"
    run "${words[0]}" general "$width" "$height" "${words[@]:1}"
  done
done
