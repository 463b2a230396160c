#!/usr/bin/env bash
# Up-front memory estimate (report/memory_check.hpp) against the measured peak resident set,
# for every program on the bundled scenes. The estimate is the summary's
# scene.memory_estimate_bytes (max over ranks: resident set at the check + what the program
# still allocates); the peak is GNU time's "Maximum resident set size" of the process (rank 0
# at 1 rank; at 2 ranks the summary's peak_memory_bytes, max over ranks).
# Usage: results/reliability/memory_estimates.sh BUILD_DIR > table.md
set -euo pipefail
build=$(cd "${1:-build}" && pwd)
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
in=$root/inputs
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} OMP_PROC_BIND=false
bake=$build/miniapps/bake/bake
sketch=$build/miniapps/sketchtrace/sketchtrace
bench=$build/bench/rtmini-bvh-bench
gen=$build/inputs/rtmini-gen-inputs

echo "| program | input and options | ranks | estimate (MiB) | peak RSS (MiB) | estimate / peak |"
echo "|---|---|---|---|---|---|"
# measure LABEL RANKS CMD...: one run, one table row.
measure() {
  local label=$1 ranks=$2
  shift 2
  rm -f s.json
  if [[ $ranks == 1 ]]; then
    /usr/bin/time -v "$@" --summary s.json >out.txt 2>time.txt || { cat time.txt >&2; exit 1; }
    peak=$(sed -n 's/.*Maximum resident set size (kbytes): \([0-9]*\)/\1/p' time.txt)
    peak=$((peak * 1024))
  else
    mpirun -np "$ranks" --oversubscribe "$@" --summary s.json >out.txt 2>time.txt ||
      { cat time.txt >&2; exit 1; }
    peak=$(python3 -c "import json; print(int(json.load(open('s.json'))['peak_memory_bytes']))")
  fi
  est=$(python3 -c "import json; print(int(json.load(open('s.json'))['scene']['memory_estimate_bytes']))")
  python3 - "$label" "$ranks" "$est" "$peak" <<'EOF'
import sys
label, ranks, est, peak = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
prog, _, rest = label.partition(" | ")
print(f"| {prog} | {rest} | {ranks} | {est / 2**20:.1f} | {peak / 2**20:.1f} | {est / peak:.2f} |")
EOF
}

measure "bake | cube.bs" 1 "$bake" "$in/cube/cube.bs" -o map.bs
measure "bake | cornell_box.bs" 1 "$bake" "$in/cornell/cornell_box.bs" -o map.bs
measure "bake | cornell_big_raw.bs" 1 "$bake" "$in/cornell_big/cornell_big_raw.bs" -o big.bs
measure "bake | cornell_big_raw.bs -n 1000 -k 3" 1 "$bake" "$in/cornell_big/cornell_big_raw.bs" -n 1000 -k 3 -o map.bs
measure "bake | cornell_big_raw.bs -n 1000 -k 3" 2 "$bake" "$in/cornell_big/cornell_big_raw.bs" -n 1000 -k 3 -o map.bs
measure "bake | CornellBox-Original.obj" 1 "$bake" "$in/meshes/CornellBox-Original.obj" -o map.bs
measure "bake | stanford-bunny.obj -n 20 -k 0" 1 "$bake" "$in/meshes/stanford-bunny.obj" -n 20 -k 0 -o map.bs
measure "bake ao | spot_instances.toml" 1 "$bake" ao "$in/ao/spot_instances.toml"
measure "bake ao | dragon.obj" 1 "$bake" ao "$in/meshes/dragon.obj"
measure "bake ao | dragon_x4.toml" 1 "$bake" ao "$in/ao/dragon_x4.toml"
measure "bake ao | dragon_x4.toml" 2 "$bake" ao "$in/ao/dragon_x4.toml"
measure "bake render | cornell_big map, 640x480" 1 "$bake" render big.bs --width 640 --height 480 -o r.png
measure "bake render | cornell_big map, 1920x1080" 1 "$bake" render big.bs --width 1920 --height 1080 -o r.png
measure "sketchtrace | two_spheres.toml" 1 "$sketch" "$in/two_spheres/two_spheres.toml" -o a.png
measure "sketchtrace | spheres.toml" 1 "$sketch" "$in/spheres/spheres.toml" -o a.png
measure "sketchtrace | watchtower.toml" 1 "$sketch" "$in/watchtower/watchtower.toml" -o a.png
measure "sketchtrace | dist_first.toml" 1 "$sketch" "$in/dist_first/dist_first.toml" -o a.png
measure "sketchtrace | dragon.obj --spp 1" 1 "$sketch" "$in/meshes/dragon.obj" --spp 1 -o a.png
measure "sketchtrace | two_spheres.toml 3840x2160 --spp 1" 1 "$sketch" "$in/two_spheres/two_spheres.toml" --width 3840 --height 2160 --spp 1 -o a.png
measure "sketchtrace | two_spheres.toml 3840x2160 --spp 1" 2 "$sketch" "$in/two_spheres/two_spheres.toml" --width 3840 --height 2160 --spp 1 -o a.png
measure "rtmini-bvh-bench | stanford-bunny.obj primary" 1 "$bench" "$in/meshes/stanford-bunny.obj" --repeats 1
measure "rtmini-bvh-bench | dragon.obj ao, 1 sample x 16 rays per face" 1 "$bench" "$in/meshes/dragon.obj" --workload ao --samples-per-face 1 --rays 16 --repeats 1
measure "rtmini-bvh-bench | dragon.obj diffuse" 1 "$bench" "$in/meshes/dragon.obj" --workload diffuse --repeats 1
measure "rtmini-gen-inputs | cornell_big" 1 "$gen" cornell_big -o gen.bs
measure "rtmini-gen-inputs | bunny" 1 "$gen" bunny --scene "$in/meshes/stanford-bunny.obj" -o gen.bs
