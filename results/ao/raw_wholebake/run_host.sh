#!/usr/bin/env bash
# Host figures of the AO whole bake per phase: baseline, branch, and branch with a one-thread OBJ
# reader alternated, five runs each, logs into this folder, medians by ../phase_medians.py.
#   bash results/ao/raw_wholebake/run_host.sh BASE_BAKE NEW_BAKE [RAYS]
# RAYS (default 4) keeps the shared 2-core VM's runs short: the phases this branch changes (load,
# sample plan, write) do not depend on it; the full 64-ray runs are logged separately (full_*.log).
set -u
base=$1 new=$2 rays=${3:-4}
dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export OMP_PROC_BIND=false
# "serial": the branch with its OBJ reader on one thread (RTMINI_OBJ_THREADS=1).
for rep in 1 2 3 4 5; do
  for t in base new serial; do
    bin=$base; [ "$t" != base ] && bin=$new
    threads=; [ "$t" = serial ] && threads=1
    RTMINI_OBJ_THREADS=$threads "$bin" ao inputs/ao/dragon_x4.toml -s 1250000 -r "$rays" --fit cg -o "/tmp/aob_$t.glb" \
      --summary "$dir/ao_${t}_$rep.json" > "$dir/ao_${t}_$rep.log" 2>&1
    echo "$t rep $rep rc=$?"
  done
done
cmp /tmp/aob_base.glb /tmp/aob_new.glb && cmp /tmp/aob_base.glb /tmp/aob_serial.glb &&
  echo "glb outputs identical"
python3 "$dir/../phase_medians.py" "$dir" | tee "$dir/medians.txt"
