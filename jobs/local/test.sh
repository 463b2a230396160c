#!/usr/bin/env bash
# README command (2): set up, build, and run the whole default test suite with ctest.
# Usage: jobs/local/test.sh [ctest arguments, e.g. -L unit]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# CI builds with warnings as errors (-Wall -Wextra -Wshadow on rtmini's own code), so a new
# warning fails it. RTMINI_WERROR=OFF in the environment keeps them warnings (for a newer
# compiler that warns where Debian 12's GCC 12 and Clang 14 do not).
"$root/jobs/local/build.sh" -DRTMINI_WERROR="${RTMINI_WERROR:-ON}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_PROC_BIND=false
cd "${RTMINI_BUILD_DIR:-$root/build}"
ctest --output-on-failure --timeout 1500 -j "${RTMINI_TEST_JOBS:-2}" "$@"
