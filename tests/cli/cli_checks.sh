#!/usr/bin/env bash
# The shared command line of every rtmini program (issue 16, part 4).
# Usage: cli_checks.sh CHECK PROGRAM [ARGS...]
#   help     PROGRAM [SUB]  --help exits 0 and its first line is the program's own ("PROGRAM[ SUB]: ...")
#   version  PROGRAM [SUB]  --version exits 0 and prints exactly one line, the build banner "rtmini ..."
#   bad-flag PROGRAM [SUB]  an unknown flag exits 2 with one stderr line "PROGRAM: reason", no core
#   bad-env  PROGRAM VAR=VALUE ARGS  the command with VAR=VALUE in its environment (a value
#                           Kokkos would abort or crash on): exit 2 and one stderr line that
#                           names VAR=VALUE, no core
#   run      PROGRAM ARGS   the command (with --threads 2 among ARGS) exits 0; a --summary FILE
#                           in ARGS holds a verification hash, a --timings FILE is HDF5
set -uo pipefail
check=$1
prog=$2
shift 2
name=$(basename "$prog")
fail() { echo "FAIL ($check $name $*)" >&2; exit 1; }
case $check in
help)
  out=$("$prog" "$@" --help) || fail "exit $?"
  want="$name${1:+ $1}:"
  first=$(printf '%s\n' "$out" | head -n 1)
  [[ $first == "$want"* ]] || fail "first line '$first' does not start with '$want'"
  ;;
version)
  out=$("$prog" "$@" --version) || fail "exit $?"
  [ "$(printf '%s\n' "$out" | wc -l)" -eq 1 ] || fail "more than one line: $out"
  [[ $out == "rtmini "*" (git "*") Kokkos "* ]] || fail "not the build banner: $out"
  ;;
bad-flag)
  err=$("$prog" "$@" --no-such-flag-xyz 2>&1 >/dev/null)
  code=$?
  [ "$code" -eq 2 ] || fail "exit $code, want 2: $err"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "more than one stderr line: $err"
  [[ $err == "$name: "* ]] || fail "stderr does not start with '$name: ': $err"
  ;;
bad-env)
  assignment=$1
  shift
  err=$(env "$assignment" "$prog" "$@" 2>&1 >/dev/null)
  code=$?
  [ "$code" -eq 2 ] || fail "exit $code, want 2: $err"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "more than one stderr line: $err"
  [[ $err == "$name: "*"$assignment: "* ]] || fail "not the line: $err"
  ;;
run)
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
  cd "$work" || fail "no work dir"
  # Unset, as for a user who never heard of them: Kokkos must not warn about OMP_PROC_BIND.
  err=$(env -u OMP_PROC_BIND -u OMP_PLACES "$prog" "$@" 2>&1 >/dev/null)
  code=$?
  [ "$code" -eq 0 ] || fail "exit $code: $err"
  [[ $err != *"OMP_PROC_BIND"* ]] || fail "Kokkos' OMP_PROC_BIND warning: $err"
  args=("$@")
  for ((i = 0; i < ${#args[@]} - 1; ++i)); do
    if [ "${args[i]}" = --summary ]; then
      grep -q '"verification_hash"' "${args[i + 1]}" || fail "no verification hash in ${args[i + 1]}"
    fi
    if [ "${args[i]}" = --timings ]; then
      [ "$(head -c 4 "${args[i + 1]}" | od -An -c | tr -d ' ')" = '211HDF' ] ||
        fail "${args[i + 1]} is not an HDF5 file"
    fi
  done
  ;;
*) fail "unknown check" ;;
esac
echo "ok: $check $name $*"
