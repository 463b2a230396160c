#!/usr/bin/env bash
# Set up (jobs/local/setup.sh) and build rtmini with the default OpenMP preset into build/.
# Usage: jobs/local/build.sh [extra cmake -D options...]
# Env:   RTMINI_BUILD_DIR (default: build), RTMINI_JOBS (default: nproc)
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
"$root/jobs/local/setup.sh"
build=${RTMINI_BUILD_DIR:-$root/build}
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
elif [ $# -gt 0 ]; then
  cmake "$build" "$@"
fi
cmake --build "$build" -j "${RTMINI_JOBS:-$(nproc)}"
