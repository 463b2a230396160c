#!/usr/bin/env bash
# The longer fuzz campaign of results/reliability/fuzz.md (issue 17): every libFuzzer target
# of tests/fuzz for SECONDS each, two at a time, under nice (the machine is shared), from the
# same seed corpora as ctest's label fuzz. Prints one line per target:
#   target execs exec/s cov ft corpus seconds findings
# and exits 1 when any target found something (crash, leak, timeout, out-of-memory; the
# reproducers are in $WORK/<target>/).
# Usage: results/reliability/fuzz_campaign.sh [SECONDS [TARGET...]]
# Env:   BUILD (the main build with bake and sketchtrace; default build), WORK (default
#        $BUILD/fuzz-campaign), LANES (targets at once; default 2)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${BUILD:-$root/build}
work=${WORK:-$build/fuzz-campaign}
seconds=${1:-600}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(obj bs bsb scene_toml ao_scene ao_options bake_checkpoint
                               sketch_checkpoint cost_map ppm png)
fuzz=$root/tests/fuzz/fuzz.sh
mkdir -p "$work"
nice bash "$fuzz" build "$work/build" >"$work/build.log"
BAKE=$build/miniapps/bake/bake SKETCH=$build/miniapps/sketchtrace/sketchtrace \
  bash "$fuzz" seeds "$work/seeds" >"$work/seeds.log"

run_one() {
  local t=$1
  nice bash "$fuzz" run "$work/build" "$work/seeds" "$work/$t" "$t" -max_total_time="$seconds" \
    >"$work/$t.log" 2>&1 || true
}
running=0
for t in "${targets[@]}"; do
  run_one "$t" &
  running=$((running + 1))
  if ((running >= ${LANES:-2})); then
    wait -n
    running=$((running - 1))
  fi
done
wait

status=0
printf '%-18s %10s %7s %6s %7s %7s %7s %s\n' target execs exec/s cov ft corpus seconds findings
for t in "${targets[@]}"; do
  log=$work/$t.log
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
  last=$(grep -E '^#[0-9]+' "$log" | tail -n 1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  corp=$(sed -n 's/.* corp: \([0-9]*\)\/.*/\1/p' <<<"$last")
  secs=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$log")
  findings=$(find "$work/$t" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' \
    -o -name 'timeout-*' -o -name 'oom-*' -o -name 'slow-unit-*' \) | wc -l)
  ((findings == 0)) || status=1
  printf '%-18s %10s %7s %6s %7s %7s %7s %s\n' "$t" "${execs:-?}" "${rate:-?}" "${cov:-?}" \
    "${ft:-?}" "${corp:-?}" "${secs:-?}" "$findings"
done
exit $status
