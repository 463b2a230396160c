#!/usr/bin/env bash
# The AO whole bake of dragon x4 on the device, before and after the device expansion of the
# receiver instances (issue 21, branch aoexpand): the AO unit tests of the branch's CUDA build
# (AoExpand.* checks the device's world triangles against the host's bit for bit), then five
# whole bakes each of a baseline build and the branch's, alternated, with their phases (the
# "upload receivers and plan" and "mesh BVHs" lines are the ones the branch changes) and
# verification hashes by results/ao/phase_medians.py.
#   OUT=DIR bash results/gpu/aoexpand_device.sh NEW_BUILD_DIR [BASE_BUILD_DIR]
# Without BASE_BUILD_DIR only the branch's bakes run. Logs: $OUT/ao_{base,new}_N.log,
# $OUT/unit_ao.txt, medians in $OUT/medians.txt.
set -u
new=$1 base=${2:-}
out=${OUT:?set OUT to the log folder}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
(cd "$new" && timeout 300 ctest -R '^unit\.ao' --output-on-failure --timeout 280 > "$out/unit_ao.txt" 2>&1
 echo "unit.ao ctests rc=$?"; grep -E "tests passed|\(Failed\)|Timeout" "$out/unit_ao.txt")
for rep in 1 2 3 4 5; do
  for t in base new; do
    dir=$new; [ "$t" = base ] && dir=$base
    [ -n "$dir" ] || continue
    timeout 60 "$dir/miniapps/bake/bake" ao inputs/ao/dragon_x4.toml -s 1250000 --fit cg \
      -o "/tmp/aoexpand_$t.glb" > "$out/ao_${t}_$rep.log" 2>&1
    echo "$t rep $rep rc=$? $(grep -E 'upload receivers|Whole bake|verification' \
      "$out/ao_${t}_$rep.log" | tr -s ' ' | tr '\n' '|')"
  done
done
[ -n "$base" ] && cmp /tmp/aoexpand_base.glb /tmp/aoexpand_new.glb && echo "glb outputs identical"
python3 "$here/../ao/phase_medians.py" "$out" | tee "$out/medians.txt"
