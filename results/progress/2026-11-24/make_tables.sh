#!/usr/bin/env bash
# tables.md of this folder: eta_table.py over every log, wall clock and (c_* logs) CPU clock.
# Usage: make_tables.sh > tables.md   (from this folder)
set -u
table=../eta_table.py
for f in c_*.log w_*.log; do
  label=()
  case $f in *ao_*) label=(--label "bake ao rays") ;; esac
  python3 "$table" "${label[@]}" "$f"
  case $f in c_*) python3 "$table" --cpu "${label[@]}" "$f" ;; esac
done
