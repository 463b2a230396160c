#!/usr/bin/env bash
# The fuzz targets (tests/fuzz/targets) as ctest runs them, and as the longer campaign
# (results/reliability/fuzz_campaign.sh) does.
#   fuzz.sh build BUILD_DIR          configure + build the clang sub-project into BUILD_DIR
#   fuzz.sh seeds SEED_DIR           assemble the seed corpora (make_seeds.sh; env BAKE, SKETCH)
#   fuzz.sh run BUILD_DIR SEED_DIR WORK_DIR TARGET LIBFUZZER_ARGS...
#                                    fuzz TARGET from its seeds: new inputs go to WORK_DIR/corpus,
#                                    anything found to WORK_DIR/ (crash-*, leak-*, timeout-*, oom-*);
#                                    exit 1 on a finding
# Env: CLANGXX (default clang++), CLANGC (default clang), RTMINI_FUZZ_OPT (default -O1).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
mode=$1
shift
case $mode in
  build)
    build=$1
    generator=()
    command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
    launcher=()
    command -v ccache >/dev/null 2>&1 &&
      launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
    if [[ ! -f $build/CMakeCache.txt ]]; then
      cmake -S "$here/targets" -B "$build" "${generator[@]}" "${launcher[@]}" \
        -DCMAKE_CXX_COMPILER="${CLANGXX:-clang++}" -DCMAKE_C_COMPILER="${CLANGC:-clang}" \
        -DRTMINI_FUZZ_OPT="${RTMINI_FUZZ_OPT:--O1}" >/dev/null
    fi
    cmake --build "$build" -j "${RTMINI_JOBS:-2}"
    ;;
  seeds)
    SOURCE=$root bash "$here/make_seeds.sh" "$1"
    ;;
  run)
    build=$1 seeds=$2 work=$3 target=$4
    shift 4
    rm -rf "$work"
    mkdir -p "$work/corpus"
    # Exit 1 on any finding (libFuzzer's own default, 77, would read as "skipped" in ctest).
    "$build/fuzz_$target" -error_exitcode=1 -timeout_exitcode=1 -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$work/" "$@" "$work/corpus" "$seeds/$target"
    ;;
  *)
    echo "fuzz.sh: unknown mode $mode" >&2
    exit 2
    ;;
esac
