#!/bin/bash
# Kernel specialisation speed-up (issue 7): each bundled scene rendered with the kernel
# specialised on its features and with --general-kernel, REPS times each, interleaved.
# Prints one CSV line per run: scene,extra,kernel,features,render_s,hash.
# Usage: run_specialisation.sh SKETCHTRACE INPUTS [REPS]
set -euo pipefail
sketch=$1
inputs=$2
reps=${3:-5}
echo "scene,extra,kernel,features,render_s,hash"
run() {  # run SCENE KERNEL EXTRA...
  local scene=$1 kernel=$2
  shift 2
  local flags=()
  [[ $kernel == general ]] && flags=(--general-kernel)
  local out
  out=$("$sketch" "$inputs/$scene/$scene.toml" --width 160 --height 120 "$@" "${flags[@]}")
  local features seconds hash
  features=$(sed -n 's/^  kernel features: \([^ ,]*\).*/\1/p' <<<"$out")
  seconds=$(sed -n 's/^  render: \([0-9.]*\) s.*/\1/p' <<<"$out")
  hash=$(tail -n 1 <<<"$out" | awk '{print $NF}')
  echo "$scene,${*:-default},$kernel,$features,$seconds,$hash"
}
for case in "two_spheres" "spheres" "watchtower" "dist_first" "two_spheres --bounces 0" \
  "spheres --bounces 0"; do
  read -r -a words <<<"$case"
  for ((i = 0; i < reps; i++)); do
    run "${words[0]}" specialised "${words[@]:1}"
    run "${words[0]}" general "${words[@]:1}"
  done
done
