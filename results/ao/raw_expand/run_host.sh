#!/usr/bin/env bash
# Host figures of the AO whole bake per phase, before and after the device expansion of the
# receiver instances (upload_plan): baseline and branch alternated, five runs each, logs into
# this folder, medians by ../phase_medians.py (the "upload receivers and plan" sub-phase is the
# one this branch changes).
#   bash results/ao/raw_expand/run_host.sh BASE_BAKE NEW_BAKE [RAYS [LOG_DIR]]
# RAYS (default 4) keeps the shared 2-core VM's runs short: the upload does not depend on it.
# Env: THREADS (OpenMP threads, default 2); FIT (default "--fit cg"; "--no_least_squares" skips
# the mapping's solve, which the upload does not depend on either, to keep one-thread runs short).
set -u
base=$1 new=$2 rays=${3:-4}
dir=${4:-$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)}
mkdir -p "$dir"
export OMP_PROC_BIND=false OMP_NUM_THREADS=${THREADS:-2}
for rep in 1 2 3 4 5; do
  for t in base new; do
    bin=$base; [ "$t" = new ] && bin=$new
    "$bin" ao inputs/ao/dragon_x4.toml -s 1250000 -r "$rays" ${FIT:---fit cg} -o "/tmp/aoexpand_$t.glb" \
      --summary "$dir/ao_${t}_$rep.json" > "$dir/ao_${t}_$rep.log" 2>&1
    echo "$t rep $rep rc=$?"
  done
done
cmp /tmp/aoexpand_base.glb /tmp/aoexpand_new.glb && echo "glb outputs identical"
python3 "$(dirname "${BASH_SOURCE[0]}")/../phase_medians.py" "$dir" | tee "$dir/medians.txt"
