#!/usr/bin/env bash
# sketchtrace regression checks, one mode per ctest test (CMakeLists.txt here).
#   reference SCENE NP   render a bundled scene small, compare with tests/reference/sketchtrace
#   same_hash SCENE      1 rank x 1 and 2 threads, 2 and 4 ranks: identical verification hash
#   restart NP           stop after 2 bands + --restart == uninterrupted (hash)
#   bad FILE             exit 2 and "file:line: reason" on stderr
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
    *) echo "unknown scene $1" >&2; exit 1 ;;
  esac
}

launch() {  # launch NP ARGS...: the app on NP ranks (no MPI: NP must be 1)
  local np=$1
  shift
  if [[ -n ${MPIEXEC:-} ]]; then
    "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$SKETCH" "$@"
  else
    "$SKETCH" "$@"
  fi
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
    set -- "$INPUTS/$scene/$scene.toml" $(scene_args "$scene") --aov depth,normal,object,cost,edge --band-rows 7
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
  restart)
    np=$1
    # shellcheck disable=SC2046
    set -- "$INPUTS/two_spheres/two_spheres.toml" $(scene_args two_spheres) --band-rows 10
    launch "$np" "$@" -o "$work/full.png" > "$work/full.txt"
    launch "$np" "$@" --checkpoint "$work/ck.h5" --stop-after-bands 2 > "$work/stop.txt"
    [[ -f $work/ck.h5 ]] || { echo "no checkpoint written" >&2; exit 1; }
    [[ ! -f $work/resumed.png ]]
    launch "$np" "$@" --restart "$work/ck.h5" -o "$work/resumed.png" > "$work/resumed.txt"
    [[ $(hash_of "$work/resumed.txt") == "$(hash_of "$work/full.txt")" ]] || { echo "restart differs" >&2; exit 1; }
    cmp "$work/full.png" "$work/resumed.png"
    # A checkpoint of other parameters is refused as bad input.
    rc=0
    launch 1 "$@" --spp 2 --restart "$work/ck.h5" > /dev/null 2> "$work/err.txt" || rc=$?
    [[ $rc == 2 ]] || { echo "mismatched restart gave exit $rc" >&2; exit 1; }
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
  timings)
    np=$1
    # shellcheck disable=SC2046
    launch "$np" "$INPUTS/two_spheres/two_spheres.toml" $(scene_args two_spheres) --band-rows 16 \
      --timings "$work/t.h5" --summary "$work/s.json" > "$work/out.txt"
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
assert summary["fom"]["unit"] == "Mrays/s" and summary["fom"]["value"] > 0
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
    for scene in two_spheres spheres watchtower dist_first; do
      # shellcheck disable=SC2046
      "$SKETCH" "$INPUTS/$scene/$scene.toml" -o "$REF/$scene.exr" $(scene_args "$scene")
    done
    ;;
  *)
    echo "unknown mode $mode" >&2
    exit 1
    ;;
esac
