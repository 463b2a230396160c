#!/usr/bin/env bash
# The one-CLI acceptance sweep of issue 16 over every installed program (and bake's two
# subcommands): --help's first line, --version, an unknown flag (one line, exit 2), and a tiny
# run with --threads 2 --summary --timings (exit 0, both files written). Prints one block per
# program and a final count; exit 1 if any check failed.
# Usage: cli_sweep.sh PREFIX   (an install prefix: PREFIX/bin programs, PREFIX/share/rtmini/inputs)
set -u
prefix=$(cd "$1" && pwd)
bin=$prefix/bin inputs=$prefix/share/rtmini/inputs
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMP_PROC_BIND=false
failed=0 checked=0
check() {  # check NAME CONDITION-EXIT-STATUS DETAIL
  checked=$((checked + 1))
  if [ "$2" -eq 0 ]; then echo "  ok    $1: $3"; else echo "  FAIL  $1: $3"; failed=$((failed + 1)); fi
}
# sweep NAME "PROGRAM [SUBCOMMAND]" "ARGS OF A TINY RUN"
sweep() {
  local name=$1 first out rc lines cmd args
  read -ra cmd <<<"$2"
  read -ra args <<<"$3"
  echo "$name"
  first=$("${cmd[@]}" --help 2>&1 | head -1)
  case "$first" in "$name:"*) check help 0 "$first" ;; *) check help 1 "$first" ;; esac
  out=$("${cmd[@]}" --version 2>&1); rc=$?
  [[ $rc -eq 0 && "$out" =~ ^rtmini\ [0-9]+\.[0-9]+\.[0-9]+\ \(git\ [0-9a-f]+\)\ Kokkos ]]
  check version $? "exit $rc: $out"
  # The unknown flag goes after a valid run's arguments, so that it is the only thing wrong.
  out=$(cd "$work" && "${cmd[@]}" "${args[@]}" --no-such-flag 2>&1); rc=$?
  lines=$(printf '%s\n' "$out" | grep -c .)
  [ $rc -eq 2 ] && [ "$lines" -eq 1 ]
  check unknown-flag $? "exit $rc, $lines line(s): $out"
  rm -f "$work/s.json" "$work/t.h5"
  out=$(cd "$work" && "${cmd[@]}" "${args[@]}" --threads 2 --summary s.json --timings t.h5 2>&1); rc=$?
  [ $rc -eq 0 ] && [ -s "$work/s.json" ] && [ -s "$work/t.h5" ]
  check threads-summary-timings $? "exit $rc, summary $(test -s "$work/s.json" && echo written || echo MISSING), timings $(test -s "$work/t.h5" && echo written || echo MISSING)"
}
# A baked map for bake render, made by the sweep's own bake run.
(cd "$work" && "$bin/bake" "$inputs/cube/cube.bs" -n 20 -k 1 -o map.bs >/dev/null 2>&1)
sweep bake "$bin/bake" "$inputs/cube/cube.bs -n 20 -k 1 -o out.bs"
sweep "bake ao" "$bin/bake ao" "$inputs/meshes/spot.obj --rays 4"
sweep "bake render" "$bin/bake render" "map.bs --width 48 --height 32 -o r.ppm"
sweep sketchtrace "$bin/sketchtrace" "$inputs/two_spheres/two_spheres.toml --width 48 --height 32 -o s.ppm"
# sketchtrace-post draws on the sweep's own sketchtrace render.
(cd "$work" && "$bin/sketchtrace" "$inputs/two_spheres/two_spheres.toml" --width 48 --height 32 \
  -o post_in.ppm >/dev/null 2>&1)
sweep sketchtrace-post "$bin/sketchtrace-post" "post_in.ppm -o post.ppm"
sweep rtmini-ao "$bin/rtmini-ao" "$inputs/meshes/spot.obj --rays 4"
sweep rtmini-gen-inputs "$bin/rtmini-gen-inputs" "cube -o cube.bs"
sweep rtmini-bvh-bench "$bin/rtmini-bvh-bench" "icosphere:2 --width 32 --height 32 --repeats 1"
sweep rtmini-bake-lookup-bench "$bin/rtmini-bake-lookup-bench" "1000"
for p in "$bin"/*; do
  case $(basename "$p") in
    bake | sketchtrace | sketchtrace-post | rtmini-ao | rtmini-gen-inputs | rtmini-bvh-bench | rtmini-bake-lookup-bench) ;;
    *) echo "$(basename "$p"): installed but not in this sweep"; failed=$((failed + 1)) ;;
  esac
done
echo "$((checked - failed)) of $checked checks passed"
[ $failed -eq 0 ]
