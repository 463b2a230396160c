#!/usr/bin/env bash
# ctest `jobs.slurm`: a real one-node Slurm (Debian slurm-wlm + munge) on
# localhost, configured in a temp dir, runs the bundled sbatch scripts with
# tiny parameters; the daemons are always stopped on exit.
# Usage: jobs/slurm/test/run_local_slurm.sh
# Environment:
#   RTMINI_BIN          dir with real `bake`/`sketchtrace` to test with [unset:
#                       $RTMINI_BUILD/miniapps/... if both exist, else the stub app]
#   RTMINI_BUILD        CMake build dir to take the apps from [build]
#   RTMINI_SLURM_WAIT   seconds to wait for all jobs [120]
#   RTMINI_SLURM_KEEP=1 keep the temp dir (logs, outputs) for inspection
# Exit: 0 pass, 1 a check failed, 77 Slurm/munge missing (ctest SKIP_RETURN_CODE).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
wait_s=${RTMINI_SLURM_WAIT:-120}

for tool in munged mungekey slurmctld slurmd sbatch squeue scontrol sinfo; do
  if ! command -v "$tool" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$tool" ]; then
    echo "SKIP: $tool not installed (apt-get install slurm-wlm munge)" >&2
    exit 77
  fi
done
export PATH=$PATH:/usr/sbin

tmp=$(mktemp -d /tmp/rtmini-slurm.XXXXXX)
chmod 755 "$tmp"
pids=()
cleanup() {
  local rc=$?
  if [ -f "$tmp/slurm.conf" ]; then
    SLURM_CONF=$tmp/slurm.conf scancel --quiet --user "$(id -un)" 2>/dev/null || true
  fi
  for pid in "${pids[@]}"; do
    kill "$pid" 2>/dev/null || true
  done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 77 ]; then
    for log in "$tmp"/log/*.log; do
      [ -f "$log" ] && { echo "--- $log (tail)"; tail -n 20 "$log"; }
    done >&2
  fi
  if [ "${RTMINI_SLURM_KEEP:-0}" = 1 ]; then
    echo "kept $tmp" >&2
  else
    rm -rf "$tmp"
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

fail() { echo "FAIL: $*" >&2; exit 1; }
mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/log" "$tmp/bin" "$tmp/out"
chmod 711 "$tmp/munge"

# --- munge with a private key and socket (no systemd in containers/CI).
mungekey --create --keyfile="$tmp/munge/munge.key" --bits=1024 >/dev/null 2>&1 ||
  dd if=/dev/urandom of="$tmp/munge/munge.key" bs=128 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
socket=$tmp/munge/munge.socket
munged --foreground --force --socket="$socket" --key-file="$tmp/munge/munge.key" \
  --pid-file="$tmp/munge/munged.pid" --seed-file="$tmp/munge/munged.seed" \
  --log-file="$tmp/log/munged.log" >"$tmp/log/munged.stdout.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "munged did not create $socket"
echo probe | munge --socket="$socket" | unmunge --socket="$socket" >/dev/null ||
  fail "munge round trip through $socket failed"

# --- slurm.conf for one node = this machine, ports picked from the PID to
# keep concurrent runs apart.
base=$((20000 + ($$ % 20000)))
node_line=$(slurmd -C | head -n1)
cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$node_line")
mem=$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<<"$node_line")
user=$(id -un)
cat >"$tmp/slurm.conf" <<CONF
ClusterName=rtmini-test
SlurmctldHost=localhost
SlurmctldPort=$base
SlurmdPort=$((base + 1))
SlurmUser=$user
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SwitchType=switch/none
MpiDefault=pmix
LaunchParameters=use_interactive_step
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MaxJobCount=1000
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
CONF
export SLURM_CONF=$tmp/slurm.conf
unset SLURM_JOB_ID SLURM_JOBID

slurmctld -D -i -f "$SLURM_CONF" >"$tmp/log/slurmctld.stdout.log" 2>&1 &
pids+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" >"$tmp/log/slurmd.stdout.log" 2>&1 &
pids+=($!)

ready=0
for _ in $(seq 60); do
  state=$(sinfo -h -n localhost -o %T 2>/dev/null || true)
  case "$state" in idle*|mixed*|allocated*) ready=1; break ;; esac
  sleep 0.5
done
[ "$ready" = 1 ] || fail "node localhost not idle after 30 s (state '${state:-none}')"
echo "slurm up: $(sinfo -h -o '%P %D %T %c')"

# --- the binaries: real ones if given or built, else the stub.
build=${RTMINI_BUILD:-$root/build}
if [ -n "${RTMINI_BIN:-}" ]; then
  bin=$RTMINI_BIN stub=0
elif [ -x "$build/miniapps/bake/bake" ] && [ -x "$build/miniapps/sketchtrace/sketchtrace" ]; then
  mkdir -p "$tmp/realbin"
  ln -s "$build/miniapps/bake/bake" "$tmp/realbin/bake"
  ln -s "$build/miniapps/sketchtrace/sketchtrace" "$tmp/realbin/sketchtrace"
  bin=$tmp/realbin stub=0
else
  ln -s "$here/stub_app.sh" "$tmp/bin/bake"
  ln -s "$here/stub_app.sh" "$tmp/bin/sketchtrace"
  bin=$tmp/bin stub=1
fi
echo "binaries: $bin (stub=$stub)"
# Tiny problems; the stub ignores them, the real apps finish in seconds.
unset RTMINI_BUILD
export RTMINI_ROOT=$root RTMINI_BIN=$bin RTMINI_APP=sketchtrace
export RTMINI_WIDTH=32 RTMINI_HEIGHT=24 RTMINI_SPP=1 RTMINI_BOUNCES=1
export RTMINI_VIEWPOINTS=4 RTMINI_ITERATIONS=1 RTMINI_RANKS_PER_NODE=$cpus
submit() { # DIR [sbatch args...] SCRIPT: submit from DIR, print the job id
  local dir=$1; shift
  mkdir -p "$dir"
  (cd "$dir" && sbatch --parsable "$@")
}

cpu_id=$(RTMINI_OUTDIR=$tmp/out/cpu submit "$tmp/out/cpu" --ntasks=2 --ntasks-per-node=2 --cpus-per-task=1 \
  "$root/jobs/slurm/cpu_node.sbatch")
chain_id=$(RTMINI_OUTDIR=$tmp/out/chain RTMINI_STUB_SEGMENTS=3 RTMINI_CHAIN_MAX=5 \
  RTMINI_TIME_LIMIT_MIN=${RTMINI_SLURM_TIME_LIMIT_MIN:-1} \
  submit "$tmp/out/chain" --ntasks=1 --ntasks-per-node=1 "$root/jobs/slurm/restart_chain.sbatch")
if [ "$stub" = 1 ]; then
  guard_id=$(RTMINI_OUTDIR=$tmp/out/guard RTMINI_STUB_SEGMENTS=5 RTMINI_CHAIN_MAX=2 \
    submit "$tmp/out/guard" --ntasks=1 --ntasks-per-node=1 "$root/jobs/slurm/restart_chain.sbatch")
fi
(cd "$tmp/out" && RTMINI_RANKS="1 2" RTMINI_OUTDIR=$tmp/out/strong \
  "$root/jobs/slurm/strong_scaling.sh" >"$tmp/out/strong.ids")
(cd "$tmp/out" && RTMINI_RANKS="1 2" RTMINI_WEAK_BASE=1 RTMINI_OUTDIR=$tmp/out/weak \
  "$root/jobs/slurm/weak_scaling.sh" >"$tmp/out/weak.ids")

deadline=$((SECONDS + wait_s))
while [ -n "$(squeue -h -o %i)" ]; do
  [ "$SECONDS" -lt "$deadline" ] || { squeue >&2; fail "jobs still queued after $wait_s s"; }
  sleep 1
done
echo "all jobs left the queue after $SECONDS s"

job_field() { # ID FIELD: one field of `scontrol show job`
  scontrol -o show job "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"
}
expect_job() { # ID STATE EXIT
  local state exit_code
  state=$(job_field "$1" JobState) exit_code=$(job_field "$1" ExitCode)
  if [ "$state" = "$2" ] && [ "$exit_code" = "$3" ]; then return 0; fi
  fail "job $1: $state exit $exit_code, expected $2 exit $3 (log: $(cat "$tmp"/out/*/*"$1".out 2>/dev/null | tail -n 5))"
}
expect_files() { # FILE...: each exists and is non-empty
  local f
  for f in "$@"; do [ -s "$f" ] || fail "missing output $f"; done
}
json_field() { # FILE KEY
  "${RTMINI_PYTHON:-python3}" -c 'import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])' "$1" "$2"
}

expect_job "$cpu_id" COMPLETED 0:0
expect_files "$tmp/out/cpu/sketchtrace-2x1".{png,json,h5}
[ "$(json_field "$tmp/out/cpu/sketchtrace-2x1.json" ranks)" = 2 ] || fail "cpu_node: summary does not say 2 ranks"
echo "ok cpu_node.sbatch: 2 ranks, outputs written"

expect_files "$tmp/out/chain/sketchtrace-chain".{png,json}
expect_job "$chain_id" COMPLETED 0:0
segments=$(cat "$tmp"/out/chain/rtmini-chain-*.out | grep -c '^rtmini chain: segment [0-9]* of')
grep -q 'finished in segment' "$tmp"/out/chain/rtmini-chain-*.out || fail "restart chain did not finish"
if [ "$stub" = 1 ]; then
  [ "$segments" = 3 ] || fail "restart chain ran $segments segments, expected 3"
  grep -q 'after 3 segment' "$tmp/out/chain/sketchtrace-chain.png" || fail "chain output not from segment 3"
  expect_job "$guard_id" COMPLETED 0:0
  guard_logs=("$tmp"/out/guard/rtmini-chain-*.out)
  [ "${#guard_logs[@]}" = 2 ] || fail "loop guard: ${#guard_logs[@]} segments ran, expected 2"
  grep -q 'RTMINI_CHAIN_MAX=2' "$tmp"/out/guard/rtmini-chain-*.out || fail "loop guard message missing"
  [ ! -e "$tmp/out/guard/sketchtrace-chain.png" ] || fail "loop guard: output written although the run never finished"
  echo "ok restart_chain.sbatch: 3 segments chained, loop guard stops at 2"
else
  echo "ok restart_chain.sbatch: finished after $segments segment(s)"
fi

while read -r id; do expect_job "$id" COMPLETED 0:0; done <"$tmp/out/strong.ids"
expect_files "$tmp/out/strong/strong-1.json" "$tmp/out/strong/strong-2.json"
[ "$(json_field "$tmp/out/strong/strong-2.json" ranks)" = 2 ] || fail "strong_scaling: 2-rank point did not run 2 ranks"
echo "ok strong_scaling.sh"
while read -r id; do expect_job "$id" COMPLETED 0:0; done <"$tmp/out/weak.ids"
expect_files "$tmp/out/weak/weak-1.json" "$tmp/out/weak/weak-2.json"
echo "ok weak_scaling.sh"
echo "PASS: Slurm job scripts"
