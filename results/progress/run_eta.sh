#!/usr/bin/env bash
# One round of the ~60-120 s progress runs of README.md, every run through cpu_clock.py (stderr
# stamped with the process's CPU clock), the load average before and after each in runs.txt.
# Usage (from a scratch folder): run_eta.sh REPO BAKE_NEW BAKE_OLD SKETCHTRACE ROUND
# BAKE_OLD: a bake binary from before the spread order (the comparison for bake render and ao).
# The folder gets map.bs and front.toml on the first round (the map of overhead.md).
set -u
repo=$(cd "$1" && pwd) new=$2 old=$3 sketch=$4 round=$5
export OMP_PROC_BIND=false
clock=(python3 "$repo/results/progress/cpu_clock.py")
stamp() { echo "$(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg) $*" >>runs.txt; }
run() {
  local name=$1
  shift
  stamp "start $name"
  nice "${clock[@]}" "$name.log" "$@" >"$name.stdout"
  stamp "end $name rc=$?"
}
if [ ! -f map.bs ]; then
  "$new" "$repo/inputs/cornell_big/cornell_big_raw.bs" -o map.bs --viewpoints 1000 --iterations 4 \
    --shadow-samples 16 --threads 2 >/dev/null
  printf '[camera]\nposition = [0, 1, 3.9]\nlook_at = [0, 1, 0]\nup = [0, 1, 0]\nfov_deg = 40\n[[meshes]]\nfile = "%s"\n' \
    "$repo/inputs/cornell_big/cornell_big_raw.bs" >front.toml
fi
render=(render map.bs --scene front.toml --width 1280 --height 960 --spp 128 --threads 2 --progress)
ao=(ao "$repo/inputs/meshes/dragon.obj" --rays 320 --threads 2 --progress)
run "c_render_new_$round" "$new" "${render[@]}" -o r_new.ppm
run "c_ao_new_$round" "$new" "${ao[@]}"
run "c_render_old_$round" "$old" "${render[@]}" -o r_old.ppm
run "c_ao_old_$round" "$old" "${ao[@]}"
run "c_sketchtrace_$round" "$sketch" "$repo/inputs/watchtower/watchtower.toml" --width 2400 \
  --height 1800 --threads 2 --progress -o w.ppm
run "c_bake_$round" "$new" "$repo/inputs/cornell_big/cornell_big_raw.bs" -n 1500 -k 5 \
  --gather-rays 1200 --batch-size 64 -o cb.bs --threads 2 --progress
