#!/usr/bin/env bash
# sketchtrace regression checks, one mode per ctest test (CMakeLists.txt here).
#   reference SCENE NP   render a bundled scene small, compare with tests/reference/sketchtrace
#   same_hash SCENE      1 rank x 1 and 2 threads, 2 and 4 ranks: identical verification hash
#   restart NP [BALANCE] stop after 2 dispatches (exit 4) + --restart on other ranks == uninterrupted
#   signal NP            SIGUSR1 mid-run -> checkpoint, exit 4; --time-limit likewise; restart == full
#   balance NP           every --balance strategy on NP ranks gives the 1-rank static hash
#   motion_balance       moving_spheres (object motion blur): 1 rank x 1 and 2 threads, 2, 3 and
#                        4 ranks with every --balance strategy give one verification hash
#   bad FILE             exit 2 and "file:line: reason" on stderr
#   bad_map              an MTL naming a missing image: exit 2 and "mtl-file:line: reason"
#   timings NP           --timings/--summary files have the documented layout
#   style                --style sketch runs the hand-drawn passes
#   make_reference       (re)writes the reference images (not a test)
# Environment: SKETCH (binary), INPUTS, REF, BAD, MPIEXEC/NPFLAG (MPI builds), PY.
set -euo pipefail
mode=$1
work=$2
shift 2
rm -rf "$work"
mkdir -p "$work"

# Reduced-size render parameters per bundled scene (the references use the same ones).
scene_args() {
  case $1 in
    two_spheres) echo "--width 160 --height 120 --spp 4 --shadow-samples 16" ;;
    spheres) echo "--width 160 --height 100 --spp 4 --shadow-samples 4" ;;
    watchtower) echo "--width 160 --height 120 --spp 4 --shadow-samples 8" ;;
    dist_first) echo "--width 200 --height 160 --spp 8 --glossy-samples 4" ;;
    moving_spheres) echo "--width 160 --height 100 --spp 8" ;;
    textured_cube) echo "--width 160 --height 120 --spp 4 --shadow-samples 4" ;;
    *) echo "unknown scene $1" >&2; exit 1 ;;
  esac
}

have_h5py() { "$PY" -c "import h5py" 2>/dev/null; }  # false on a host without it (the CUDA one)

launch() {  # launch NP ARGS...: the app on NP ranks (no MPI: NP must be 1)
  local np=$1
  shift
  if [[ -n ${MPIEXEC:-} ]]; then
    "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$SKETCH" "$@"
  else
    "$SKETCH" "$@"
  fi
}

descendants() {  # descendants PID: every process below PID
  local c
  for c in $(pgrep -P "$1"); do
    echo "$c"
    descendants "$c"
  done
}

hash_of() {  # the verification hash from a run's last stdout line
  tail -n 1 "$1" | sed -n 's/.*verification \([0-9a-f]*\)$/\1/p'
}

case $mode in
  reference)
    scene=$1
    np=$2
    # shellcheck disable=SC2046
    launch "$np" "$INPUTS/$scene/$scene.toml" -o "$work/$scene.exr" $(scene_args "$scene") \
      --reference "$REF/$scene.exr" --max-rmse 0.005 --summary "$work/summary.json" | tee "$work/out.txt"
    grep -q "PASS" "$work/out.txt"
    ;;
  same_hash)
    scene=$1
    # shellcheck disable=SC2046
    set -- "$INPUTS/$scene/$scene.toml" $(scene_args "$scene") --aov depth,normal,object,cost,edge --chunk-pixels 700
    OMP_NUM_THREADS=1 launch 1 "$@" > "$work/t1.txt"
    OMP_NUM_THREADS=2 launch 1 "$@" > "$work/t2.txt"
    ref=$(hash_of "$work/t1.txt")
    [[ -n $ref ]] || { echo "no hash in the 1-thread run" >&2; exit 1; }
    [[ $(hash_of "$work/t2.txt") == "$ref" ]] || { echo "2 threads differ" >&2; exit 1; }
    if [[ -n ${MPIEXEC:-} ]]; then
      for np in 2 4; do
        OMP_NUM_THREADS=1 launch "$np" "$@" > "$work/np$np.txt"
        [[ $(hash_of "$work/np$np.txt") == "$ref" ]] || { echo "$np ranks differ" >&2; exit 1; }
      done
    fi
    echo "hash $ref identical for all thread and rank counts"
    ;;
  motion_balance)
    # shellcheck disable=SC2046
    set -- "$INPUTS/moving_spheres/moving_spheres.toml" --width 96 --height 60 --spp 4 --chunk-pixels 256
    OMP_NUM_THREADS=1 launch 1 "$@" > "$work/t1.txt"
    ref=$(hash_of "$work/t1.txt")
    [[ -n $ref ]] || { echo "no hash in the 1-rank run" >&2; exit 1; }
    grep -q "kernel features:.*motion" "$work/t1.txt" || { echo "the motion kernel did not run" >&2; exit 1; }
    OMP_NUM_THREADS=2 launch 1 "$@" > "$work/t2.txt"
    [[ $(hash_of "$work/t2.txt") == "$ref" ]] || { echo "2 threads differ" >&2; exit 1; }
    if [[ -n ${MPIEXEC:-} ]]; then
      for np in 2 3 4; do
        for b in static metric chunks bargain queue steal; do
          OMP_NUM_THREADS=1 launch "$np" "$@" --balance "$b" > "$work/np${np}_$b.txt"
          [[ $(hash_of "$work/np${np}_$b.txt") == "$ref" ]] ||
            { echo "--balance $b on $np ranks differs" >&2; exit 1; }
        done
      done
    fi
    echo "hash $ref identical for every thread count, rank count and balancer"
    ;;
  restart)
    np=$1
    balance=${2:-static}
    # shellcheck disable=SC2046
    set -- "$INPUTS/two_spheres/two_spheres.toml" $(scene_args two_spheres) --chunk-pixels 1000
    launch 1 "$@" -o "$work/full.png" > "$work/full.txt"
    rc=0
    launch "$np" "$@" --balance "$balance" --checkpoint "$work/ck.h5" --stop-after-chunks 2 -o "$work/stop.png" \
      > "$work/stop.txt" || rc=$?
    [[ $rc == 4 ]] || { echo "a stopped run gave exit $rc, expected 4" >&2; exit 1; }
    [[ -f $work/ck.h5 ]] || { echo "no checkpoint written" >&2; exit 1; }
    [[ ! -f $work/stop.png ]] || { echo "a stopped run wrote its image" >&2; exit 1; }
    # Resume on another rank count with another strategy: only the missing pixels are rendered.
    resume_np=$((np == 1 ? 2 : 1))
    [[ -n ${MPIEXEC:-} ]] || resume_np=1
    launch "$resume_np" "$@" --balance metric --restart "$work/ck.h5" -o "$work/resumed.png" > "$work/resumed.txt"
    missing=$(sed -n 's/.*balance: metric, \([0-9]*\) pixels to render.*/\1/p' "$work/resumed.txt")
    [[ -n $missing && $missing -gt 0 && $missing -lt 19200 ]] || { echo "restart rendered '$missing' pixels" >&2; exit 1; }
    [[ $(hash_of "$work/resumed.txt") == "$(hash_of "$work/full.txt")" ]] || { echo "restart differs" >&2; exit 1; }
    cmp "$work/full.png" "$work/resumed.png"
    # A checkpoint of other parameters is refused as bad input.
    rc=0
    launch 1 "$@" --spp 2 --restart "$work/ck.h5" > /dev/null 2> "$work/err.txt" || rc=$?
    [[ $rc == 2 ]] || { echo "mismatched restart gave exit $rc" >&2; exit 1; }
    ;;
  signal)
    np=$1
    # Heavy enough (several seconds) that the signal lands mid-run on any machine we test on.
    set -- "$INPUTS/two_spheres/two_spheres.toml" --width 320 --height 240 --spp 64 --shadow-samples 16 \
      --balance steal --chunk-pixels 256
    launch "$np" "$@" > "$work/full.txt"
    rc=0
    launch "$np" "$@" --checkpoint "$work/ck.h5" --checkpoint-interval 0.2 > "$work/sig.txt" 2> "$work/sig.err" &
    pid=$!
    for _ in $(seq 200); do [[ -s $work/ck.h5 ]] && break; sleep 0.05; done
    # Signal only this run's app processes (ctest runs other tests beside this one).
    for p in $(descendants "$pid"); do
      [[ $(ps -o comm= -p "$p" 2> /dev/null) == sketchtrace ]] && kill -USR1 "$p"
    done
    wait "$pid" || rc=$?
    cat "$work/sig.err"
    [[ $rc == 4 ]] || { echo "SIGUSR1 gave exit $rc, expected 4" >&2; exit 1; }
    grep -q "stop signal" "$work/sig.err" || { echo "no stop message" >&2; exit 1; }
    launch "$np" "$@" --restart "$work/ck.h5" > "$work/resumed.txt"
    [[ $(hash_of "$work/resumed.txt") == "$(hash_of "$work/full.txt")" ]] || { echo "signal restart differs" >&2; exit 1; }
    # --time-limit (minutes) of about 1 s: stops in time, exit 4, restart completes it.
    rc=0
    launch "$np" "$@" --checkpoint "$work/ck2.h5" --time-limit 0.02 > /dev/null 2> "$work/tl.err" || rc=$?
    [[ $rc == 4 ]] || { echo "--time-limit gave exit $rc, expected 4" >&2; exit 1; }
    grep -q "time limit" "$work/tl.err" || { echo "no time-limit message" >&2; exit 1; }
    launch "$np" "$@" --restart "$work/ck2.h5" > "$work/resumed2.txt"
    [[ $(hash_of "$work/resumed2.txt") == "$(hash_of "$work/full.txt")" ]] || { echo "time-limit restart differs" >&2; exit 1; }
    echo "signal and time-limit stops resume to the uninterrupted hash"
    ;;
  balance)
    np=$1
    # shellcheck disable=SC2046
    set -- "$INPUTS/two_spheres/two_spheres.toml" $(scene_args two_spheres) --chunk-pixels 512
    launch 1 "$@" > "$work/ref.txt"
    ref=$(hash_of "$work/ref.txt")
    [[ -n $ref ]] || { echo "no hash in the reference run" >&2; exit 1; }
    for b in static metric chunks bargain queue steal; do
      launch "$np" "$@" --balance "$b" --timings "$work/$b.h5" > "$work/$b.txt"
      [[ $(hash_of "$work/$b.txt") == "$ref" ]] || { echo "--balance $b on $np ranks differs" >&2; exit 1; }
      have_h5py || continue
      "$PY" -c "import h5py,sys; f=h5py.File(sys.argv[1]); s=f.attrs['strategy']; s=s.decode() if isinstance(s,bytes) else s; assert s==sys.argv[2], s; assert f['/chunks/work_units'][:].sum()==160*120" "$work/$b.h5" "$b"
    done
    for b in bargain steal; do  # the same without the communication thread (default on)
      launch "$np" "$@" --balance "$b" --comm-thread off > "$work/${b}_nothread.txt"
      [[ $(hash_of "$work/${b}_nothread.txt") == "$ref" ]] || { echo "--balance $b --comm-thread off on $np ranks differs" >&2; exit 1; }
      grep -q "communication thread: off" "$work/${b}_nothread.txt" || { echo "--comm-thread off not reported" >&2; exit 1; }
      grep -q "communication thread: on" "$work/$b.txt" || { echo "$b: communication thread not on by default" >&2; exit 1; }
    done
    rc=0
    launch 1 "$@" --balance nonsense > /dev/null 2> "$work/err.txt" || rc=$?
    if [[ $rc != 2 ]] || ! grep -q "balance" "$work/err.txt"; then
      echo "--balance nonsense: exit $rc" >&2
      exit 1
    fi
    echo "hash $ref identical for every strategy on $np ranks"
    ;;
  bad)
    file=$1
    rc=0
    "$SKETCH" "$BAD/$file" -o "$work/x.png" > "$work/out.txt" 2> "$work/err.txt" || rc=$?
    cat "$work/err.txt"
    [[ $rc == 2 ]] || { echo "expected exit 2, got $rc" >&2; exit 1; }
    grep -Eq "$file:[0-9]+: " "$work/err.txt" || { echo "no file:line: in the message" >&2; exit 1; }
    [[ ! -e $work/x.png ]]
    ;;
  bad_map)
    rc=0
    "$SKETCH" "$BAD/missing_map.obj" -o "$work/x.png" > "$work/out.txt" 2> "$work/err.txt" || rc=$?
    cat "$work/err.txt"
    [[ $rc == 2 ]] || { echo "expected exit 2, got $rc" >&2; exit 1; }
    grep -Eq "missing_map.mtl:5: .*no_such_texture.png" "$work/err.txt" ||
      { echo "no mtl-file:line: in the message" >&2; exit 1; }
    [[ ! -e $work/x.png ]]
    ;;
  timings)
    np=$1
    # shellcheck disable=SC2046
    launch "$np" "$INPUTS/two_spheres/two_spheres.toml" $(scene_args two_spheres) --chunk-pixels 512 \
      --timings "$work/t.h5" --summary "$work/s.json" > "$work/out.txt"
    have_h5py || { echo "skipped: the run passed; $PY has no h5py to read t.h5"; exit 77; }
    "$PY" - "$work/t.h5" "$work/s.json" "$np" <<'PYEOF'
import json, sys
import h5py
t, s, np_ = sys.argv[1], sys.argv[2], int(sys.argv[3])
with h5py.File(t, "r") as f:
    assert f.attrs["app"] in (b"sketchtrace", "sketchtrace")
    assert f["/phases/start"].shape[0] == np_
    assert f["/ranks/rays"].shape == (np_,)
    assert f["/chunks/rays"][:].sum() == f["/ranks/rays"][:].sum() > 0
    assert f["/chunks/work_units"][:].sum() == 160 * 120
summary = json.load(open(s))
assert summary["app"] == "sketchtrace" and summary["ranks"] == np_
assert summary["figure_of_merit"]["unit"] == "Mrays/s" and summary["figure_of_merit"]["value"] > 0
print("timings and summary OK")
PYEOF
    ;;
  style)
    # shellcheck disable=SC2046
    "$SKETCH" "$INPUTS/two_spheres/two_spheres.toml" $(scene_args two_spheres) --style sketch \
      -o "$work/sketch.png" --aov edge > "$work/out.txt"
    [[ -s $work/sketch.png && -s $work/sketch.aov.exr ]]
    ;;
  make_reference)
    for scene in two_spheres spheres watchtower dist_first moving_spheres textured_cube; do
      # shellcheck disable=SC2046
      "$SKETCH" "$INPUTS/$scene/$scene.toml" -o "$REF/$scene.exr" $(scene_args "$scene")
    done
    ;;
  *)
    echo "unknown mode $mode" >&2
    exit 1
    ;;
esac
