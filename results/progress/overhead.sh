#!/usr/bin/env bash
# Usage: overhead.sh OLD_BAKE NEW_BAKE RUNS WIDTH HEIGHT -> lines "binary mode render-seconds"
# Every run goes through script(1) so each has its own session (and scheduler autogroup) and
# the three modes compete for the CPU alike: none (stderr not a terminal, no --progress),
# log (--progress into a file: a line every 2 s), tty (stderr a terminal: redraw every 0.5 s).
set -u
export OMP_PROC_BIND=false
args="render map.bs --scene front.toml --width $4 --height $5 --spp 16 --threads 2 -o r.ppm"
for i in $(seq 1 "$3"); do
  for b in old new; do
    bin=$1; [ $b = new ] && bin=$2
    for mode in none log tty; do
      case $mode in
        none) out=$(script -qec "nice $bin $args 2>/dev/null" /dev/null) ;;
        log) out=$(script -qec "nice $bin $args --progress 2>progress.log" /dev/null) ;;
        tty) out=$(script -qec "nice $bin $args" /dev/null) ;;
      esac
      echo "$b $mode $(echo "$out" | grep rendered | sed 's/.* in \([0-9.]*\) s.*/\1/')"
    done
  done
done
