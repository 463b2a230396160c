#!/usr/bin/env bash
# Collective failure checks (issue 17): a failure seen by some ranks only must end
# the whole job within seconds, every rank with the same exit code, and rank 0
# must print exactly one "app...: file...: reason" line. Before the collective
# outcome these runs hung until killed.
#   one_rank APP NP      the input missing, then malformed, on the last rank only
#                        and on rank 0 only (MPMD launch: the other ranks get a good file)
#   sketch_restart NP    sketchtrace --restart with a checkpoint of other parameters
#   sketch_reference NP  sketchtrace --reference naming a file that does not exist
# Environment: SKETCH, BAKE (binaries), INPUTS, BAD (bad bake inputs), SKETCH_BAD,
# MPIEXEC, NPFLAG.
set -euo pipefail
mode=$1
work=$2
shift 2
rm -rf "$work"
mkdir -p "$work"
cd "$work"
limit=25  # seconds a failing run may take; a hang is killed here and reported

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# expect_one_line APP EXPECT_CODE PATTERN CMD...: runs CMD, which must exit EXPECT_CODE
# within $limit seconds and leave exactly one line of APP's on stderr, matching PATTERN.
expect_one_line() {
  local app=$1 want=$2 pattern=$3
  shift 3
  local rc=0 start end
  start=$(date +%s)
  timeout -k 5 "$limit" "$@" >out.txt 2>err.txt || rc=$?
  end=$(date +%s)
  [[ $rc != 124 && $rc != 137 ]] || fail "hung: no exit within $limit s: $*"
  [[ $rc == "$want" ]] || { cat err.txt >&2; fail "exit $rc, expected $want: $*"; }
  local lines
  lines=$(grep -c "^$app" err.txt || true)
  [[ $lines == 1 ]] || { cat err.txt >&2; fail "$lines lines of $app on stderr, expected 1: $*"; }
  grep "^$app" err.txt | grep -Eq -- "$pattern" ||
    { cat err.txt >&2; fail "the line does not match '$pattern': $*"; }
  echo "ok ($((end - start)) s): $(grep "^$app" err.txt)"
}

sketch_args=(--width 80 --height 60 --spp 1 --shadow-samples 2)
bake_args=(--viewpoints 10)

case $mode in
  one_rank)
    app=$1
    np=$2
    if [[ $app == sketchtrace ]]; then
      bin=$SKETCH good=$INPUTS/two_spheres/two_spheres.toml malformed=$SKETCH_BAD/unknown_key.toml
      args=("${sketch_args[@]}" -o out.png)
    else
      bin=$BAKE good=$INPUTS/cube/cube.bs malformed=$BAD/bs_nan.bs
      args=("${bake_args[@]}" -o out.bs)
    fi
    for bad in "$work/missing_input" "$malformed"; do
      name=$(basename "$bad")
      # the last rank only
      expect_one_line "$app" 2 "\\(rank $((np - 1))\\): .*$name" \
        "$MPIEXEC" "$NPFLAG" $((np - 1)) --oversubscribe "$bin" "$good" "${args[@]}" : \
        "$NPFLAG" 1 --oversubscribe "$bin" "$bad" "${args[@]}"
      # rank 0 only
      expect_one_line "$app" 2 "\\(rank 0\\): .*$name" \
        "$MPIEXEC" "$NPFLAG" 1 --oversubscribe "$bin" "$bad" "${args[@]}" : \
        "$NPFLAG" $((np - 1)) --oversubscribe "$bin" "$good" "${args[@]}"
      [[ ! -e out.png && ! -e out.bs ]] || fail "a failed run left its output"
    done
    # Every rank failing the same way names no rank.
    expect_one_line "$app" 2 "^$app: .*$(basename "$malformed")" \
      "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$bin" "$malformed" "${args[@]}"
    ;;
  sketch_restart)
    np=$1
    set -- "$INPUTS/two_spheres/two_spheres.toml" --width 80 --height 60 --shadow-samples 2 --chunk-pixels 500
    rc=0
    "$SKETCH" "$@" --spp 1 --checkpoint ck.h5 --stop-after-chunks 2 >stop.txt 2>&1 || rc=$?
    [[ $rc == 4 && -f ck.h5 ]] || fail "the stopped run gave exit $rc and no checkpoint"
    expect_one_line sketchtrace 2 "ck.h5: checkpoint was written with different parameters" \
      "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$SKETCH" "$@" --spp 2 --restart ck.h5
    ;;
  sketch_reference)
    np=$1
    expect_one_line sketchtrace 2 "nonexistent.exr" \
      "$MPIEXEC" "$NPFLAG" "$np" --oversubscribe "$SKETCH" "$INPUTS/two_spheres/two_spheres.toml" \
      "${sketch_args[@]}" --reference "$work/nonexistent.exr"
    ;;
  *)
    fail "unknown mode $mode"
    ;;
esac
