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
# Open MPI starts a helper daemon for every program run without mpirun (a "singleton"): 0.64 s
# per launch here against 0.40 s isolated, over the suite's hundreds of single-process runs. No
# test spawns processes, which is all an isolated singleton cannot do.
export OMPI_MCA_ess_singleton_isolated=${OMPI_MCA_ess_singleton_isolated:-1}
export OMP_PROC_BIND=false
cd "${RTMINI_BUILD_DIR:-$root/build}"
ctest --output-on-failure --timeout 1500 -j "${RTMINI_TEST_JOBS:-2}" "$@"
