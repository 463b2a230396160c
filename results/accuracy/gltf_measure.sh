#!/usr/bin/env bash
# glTF input (issue 24): what reading the three Spot instances from a glTF instead of the OBJ
# changes in bake --mode ao (the glTF's float positions), and the load phase of both scenes,
# interleaved. Usage: results/accuracy/gltf_measure.sh BUILD_DIR [RUNS]   (writes raw_gltf/)
set -euo pipefail
build=$1
runs=${2:-7}
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
out=$root/results/accuracy/raw_gltf
mkdir -p "$out"
ao=$build/miniapps/bake/ao/rtmini-ao
export OMP_NUM_THREADS=1 OMP_PROC_BIND=false
{
  echo "# $(date -u +%FT%TZ) $(git -C "$root" rev-parse --short HEAD) $(uname -n) load: $(cut -d' ' -f1-3 /proc/loadavg)"
  for s in spot_instances spot_gltf; do
    "$ao" "$root/inputs/ao/$s.toml" --rays 16 --passes 4 --batch 5000 -o "$out/$s.bin" >"$out/$s.log"
    grep -E "^rtmini|verification" "$out/$s.log"
  done
  echo "vertices,rms_diff,mean_diff,max_abs_diff,mean_ao_ref (spot_gltf vs spot_instances)"
  /usr/bin/python3 "$root/results/accuracy/ao_compare.py" "$out/spot_gltf.bin" "$out/spot_instances.bin"
  echo "run,scene,load_ms"
  for i in $(seq "$runs"); do
    for s in spot_instances spot_gltf; do
      ms=$("$ao" "$root/inputs/ao/$s.toml" --rays 1 --no-least-squares | awk '/^Load scene/ {print $4}')
      echo "$i,$s,$ms"
    done
  done
} | tee "$out/measure.log"
rm -f "$out"/*.bin
