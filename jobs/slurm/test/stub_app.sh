#!/usr/bin/env bash
# Stand-in for `bake`/`sketchtrace` in the job-script tests: honours the run
# contract's file options and exit codes without tracing anything.
#   RTMINI_STUB_SECONDS   run time the summary reports (default 1.0)
#   RTMINI_STUB_SEGMENTS  segments a checkpointed run needs (default 1); each
#                         earlier segment writes the checkpoint and exits 4.
# Only rank 0 writes files; other ranks exit 0, so srun/mpirun report rank 0's code.
set -euo pipefail

app=$(basename "$0")
out="" summary="" timings="" checkpoint="" restart=""
while [ $# -gt 0 ]; do
  case "$1" in
    -o) out=$2; shift ;;
    --summary) summary=$2; shift ;;
    --timings) timings=$2; shift ;;
    --checkpoint) checkpoint=$2; shift ;;
    --restart) restart=$2; shift ;;
    --version) echo "$app stub 0.0"; exit 0 ;;
    --*) [ $# -gt 1 ] && [ "${2#--}" = "$2" ] && shift ;;
    *) ;;
  esac
  shift
done
[ -n "$out" ] || { echo "$app: -o is required" >&2; exit 2; }

rank=${SLURM_PROCID:-${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-0}}}
ranks=${SLURM_NTASKS:-${OMPI_COMM_WORLD_SIZE:-${PMI_SIZE:-1}}}
[ "$rank" -eq 0 ] || exit 0

atomic_write() { # FILE CONTENT: temp then rename, as the real apps do
  printf '%s\n' "$2" >"$1.tmp.$$" && mv "$1.tmp.$$" "$1"
}

segment=1
if [ -n "$restart" ]; then
  [ -s "$restart" ] || { echo "$restart:1: missing checkpoint" >&2; exit 2; }
  segment=$(($(sed -n 's/^segment //p' "$restart") + 1))
fi
if [ -n "$checkpoint" ] && [ "$segment" -lt "${RTMINI_STUB_SEGMENTS:-1}" ]; then
  atomic_write "$checkpoint" "segment $segment"
  echo "$app: time limit reached in segment $segment; checkpoint $checkpoint" >&2
  exit 4
fi

atomic_write "$out" "$app stub output after $segment segment(s)"
[ -z "$timings" ] || atomic_write "$timings" "stub timings"
if [ -n "$summary" ]; then
  atomic_write "$summary" "{\"app\": \"$app\", \"version\": \"stub\", \"git_hash\": \"unknown\",
 \"backend\": \"stub\", \"ranks\": $ranks, \"threads\": ${OMP_NUM_THREADS:-1},
 \"scene\": {}, \"parameters\": {\"segments\": $segment}, \"phases\": {\"total\": ${RTMINI_STUB_SECONDS:-1.0}},
 \"figure_of_merit\": {\"name\": \"stub\", \"value\": 1.0, \"unit\": \"1\"},
 \"verification_hash\": \"0\", \"peak_memory_bytes\": 0}"
fi
echo "$app stub: FOM 1.0 hash 0 segments $segment ranks $ranks"
