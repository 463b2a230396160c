#!/usr/bin/env bash
# Verification hash of each render below with two sketchtrace binaries (host builds), e.g. main's
# and a branch's: "same" where they agree. Run from the root of a checkout.
#   bash results/gpu/raw_sketchlobe/hash_check.sh SKETCHTRACE_A SKETCHTRACE_B
A=$1 B=$2
here=results/gpu/raw_sketchlobe
runs=(
  "$here/all_lights.toml"
  "$here/all_lights.toml --soft-shadows off"
  "$here/all_lights.toml --shadow-samples 9"
  "$here/all_lights.toml --indirect on --bounces 2"
  "inputs/dist_first/dist_first.toml --width 80 --height 64 --spp 2 --soft-shadows off"
  "inputs/dist_first/dist_first.toml --width 80 --height 64 --spp 2 --shadow-samples 9"
  "inputs/two_spheres/two_spheres.toml --width 80 --height 48 --spp 2 --soft-shadows off"
  "inputs/spheres/spheres.toml --width 80 --height 48 --spp 2"
  "inputs/light_converge/glass.toml"
  "inputs/light_converge/penumbra.toml"
  "inputs/light_converge/reflected_shadow.toml --bounces 0"
)
out=$(mktemp -d)
for r in "${runs[@]}"; do
  # shellcheck disable=SC2086
  ha=$("$A" $r --threads 2 -o "$out/a.png" 2>&1 | awk '/verification/{print $NF}')
  # shellcheck disable=SC2086
  hb=$("$B" $r --threads 2 -o "$out/b.png" 2>&1 | awk '/verification/{print $NF}')
  [ -n "$ha" ] && [ "$ha" = "$hb" ] && st=same || st=DIFF
  echo "$st $ha $hb | $r"
done
rm -rf "$out"
