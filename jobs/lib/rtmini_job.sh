# shellcheck shell=bash
# Shared helpers for the rtmini job scripts (Slurm, Cobalt, local mpirun).
# Sourced, never executed. Every knob is an environment variable; the header
# of each job script lists the ones it reads and their defaults.
#
#   RTMINI_ROOT       repository root (default: the caller's guess, see rtmini_init)
#   RTMINI_BUILD      CMake build dir (default: $RTMINI_ROOT/build)
#   RTMINI_BIN        dir holding the `bake`/`sketchtrace` binaries; overrides
#                     $RTMINI_BUILD/miniapps/<app>/<app>
#   RTMINI_APP        sketchtrace | bake (default: sketchtrace)
#   RTMINI_INPUT      scene/mesh (default: inputs/two_spheres/two_spheres.toml for
#                     sketchtrace, inputs/cornell/cornell_box.bs for bake)
#   RTMINI_OUTDIR     where outputs go (default: $PWD/rtmini-out)
#   RTMINI_TAG        file-name stem for this run (default: <app>)
#   sketchtrace:      RTMINI_WIDTH RTMINI_HEIGHT RTMINI_SPP RTMINI_SHADOW_SAMPLES
#                     RTMINI_BOUNCES RTMINI_BALANCE (unset = app default)
#   bake:             RTMINI_VIEWPOINTS (100) RTMINI_ITERATIONS (4)
#                     RTMINI_SHADOW_SAMPLES RTMINI_GATHER_RAYS RTMINI_SEED RTMINI_BALANCE
#                     RTMINI_NODE_SHARING (on: the ranks of a node read one copy of the
#                     scene and take each other's work; scene, work: one of the two; for
#                     several ranks per node on CPUs)
#   RTMINI_EXTRA_ARGS extra app arguments, split on whitespace
#   RTMINI_ENV_HOOK   a bash file sourced by rtmini_init before anything runs: the site's
#                     `module load` lines (compiler, MPI, HDF5, CUDA, Kokkos) (default: none)
#   RTMINI_PYTHON     Python with numpy, matplotlib and h5py for the analysis tools
#                     (default: python3 on PATH; on Debian /usr/bin/python3)

# rtmini_init DEFAULT_ROOT: set RTMINI_ROOT/RTMINI_BUILD/RTMINI_APP/RTMINI_OUTDIR.
rtmini_init() {
  if [ -n "${RTMINI_ENV_HOOK:-}" ]; then
    [ -r "$RTMINI_ENV_HOOK" ] || { echo "rtmini: RTMINI_ENV_HOOK=$RTMINI_ENV_HOOK is not readable" >&2; exit 2; }
    # shellcheck source=/dev/null
    source "$RTMINI_ENV_HOOK"
  fi
  RTMINI_ROOT=${RTMINI_ROOT:-$1}
  RTMINI_BUILD=${RTMINI_BUILD:-$RTMINI_ROOT/build}
  RTMINI_APP=${RTMINI_APP:-sketchtrace}
  RTMINI_OUTDIR=${RTMINI_OUTDIR:-$PWD/rtmini-out}
  RTMINI_TAG=${RTMINI_TAG:-$RTMINI_APP}
  case "$RTMINI_APP" in
    sketchtrace | bake) ;;
    *) echo "rtmini: RTMINI_APP must be sketchtrace or bake, not '$RTMINI_APP'" >&2; exit 2 ;;
  esac
  mkdir -p "$RTMINI_OUTDIR"
}

# rtmini_binary APP: print the path of the app binary, or exit 3 if missing.
rtmini_binary() {
  local app=$1 exe
  if [ -n "${RTMINI_BIN:-}" ]; then
    exe=$RTMINI_BIN/$app
  else
    exe=$RTMINI_BUILD/miniapps/$app/$app
  fi
  if [ ! -x "$exe" ]; then
    echo "rtmini: no executable $exe (build it, or set RTMINI_BUILD / RTMINI_BIN)" >&2
    exit 3
  fi
  printf '%s\n' "$exe"
}

# rtmini_default_input APP: the bundled input used when RTMINI_INPUT is unset.
rtmini_default_input() {
  if [ "$1" = bake ]; then
    printf '%s\n' "$RTMINI_ROOT/inputs/cornell/cornell_box.bs"
  else
    printf '%s\n' "$RTMINI_ROOT/inputs/two_spheres/two_spheres.toml"
  fi
}

# rtmini_image_ext: the image format a run writes by default: png when the build has libpng,
# else exr when it has OpenEXR, else ppm (always built in). Read from the build's
# rtmini_features.env (written by CMake); without one (RTMINI_BIN, no build dir): ppm.
rtmini_image_ext() {
  local features=$RTMINI_BUILD/rtmini_features.env
  if grep -qx 'RTMINI_HAVE_PNG=ON' "$features" 2>/dev/null; then
    echo png
  elif grep -qx 'RTMINI_HAVE_EXR=ON' "$features" 2>/dev/null; then
    echo exr
  else
    echo ppm
  fi
}

# rtmini_app_args: fill the array RTMINI_ARGS with input, output and knobs
# for $RTMINI_APP, writing outputs as $RTMINI_OUTDIR/$RTMINI_TAG.*.
rtmini_app_args() {
  local stem=$RTMINI_OUTDIR/$RTMINI_TAG
  RTMINI_ARGS=("${RTMINI_INPUT:-$(rtmini_default_input "$RTMINI_APP")}")
  if [ "$RTMINI_APP" = bake ]; then
    RTMINI_ARGS+=(-o "$stem.bs" --viewpoints "${RTMINI_VIEWPOINTS:-100}"
      --iterations "${RTMINI_ITERATIONS:-4}")
    [ -n "${RTMINI_GATHER_RAYS:-}" ] && RTMINI_ARGS+=(--gather-rays "$RTMINI_GATHER_RAYS")
    [ -n "${RTMINI_SEED:-}" ] && RTMINI_ARGS+=(--seed "$RTMINI_SEED")
    [ -n "${RTMINI_NODE_SHARING:-}" ] && RTMINI_ARGS+=(--node-sharing "$RTMINI_NODE_SHARING")
  else
    RTMINI_ARGS+=(-o "$stem.${RTMINI_IMAGE_EXT:-png}")
    [ -n "${RTMINI_WIDTH:-}" ] && RTMINI_ARGS+=(--width "$RTMINI_WIDTH")
    [ -n "${RTMINI_HEIGHT:-}" ] && RTMINI_ARGS+=(--height "$RTMINI_HEIGHT")
    [ -n "${RTMINI_SPP:-}" ] && RTMINI_ARGS+=(--spp "$RTMINI_SPP")
    [ -n "${RTMINI_BOUNCES:-}" ] && RTMINI_ARGS+=(--bounces "$RTMINI_BOUNCES")
  fi
  [ -n "${RTMINI_SHADOW_SAMPLES:-}" ] && RTMINI_ARGS+=(--shadow-samples "$RTMINI_SHADOW_SAMPLES")
  [ -n "${RTMINI_BALANCE:-}" ] && RTMINI_ARGS+=(--balance "$RTMINI_BALANCE")
  RTMINI_ARGS+=(--summary "$stem.json" --timings "$stem.h5")
  if [ -n "${RTMINI_EXTRA_ARGS:-}" ]; then
    local extra
    read -r -a extra <<<"$RTMINI_EXTRA_ARGS"
    RTMINI_ARGS+=("${extra[@]}")
  fi
  return 0
}

# rtmini_banner LAUNCHER...: echo what is about to run (XSBench-style provenance).
rtmini_banner() {
  echo "rtmini job: $(date -u +%Y-%m-%dT%H:%M:%SZ) host=$(hostname) app=$RTMINI_APP"
  echo "rtmini job: git $(git -C "$RTMINI_ROOT" rev-parse --short=12 HEAD 2>/dev/null || echo unknown)"
  echo "rtmini job: command: $*"
}

# rtmini_checkpoint_args CKPT MINUTES: append checkpoint/restart options to
# RTMINI_ARGS; --restart only when a previous segment left CKPT behind.
rtmini_checkpoint_args() {
  RTMINI_ARGS+=(--checkpoint "$1" --time-limit "$2")
  if [ -s "$1" ]; then
    RTMINI_ARGS+=(--restart "$1")
  fi
}

# rtmini_chain_decision RC COUNT MAX CKPT: decide what a restart-chain segment
# does after the app exited with RC. Prints done, resubmit or fail.
# A chain stops at MAX segments so a run that never finishes cannot loop forever.
rtmini_chain_decision() {
  local rc=$1 count=$2 max=$3 ckpt=$4
  if [ "$rc" -eq 0 ]; then
    echo "done"
  elif [ "$rc" -eq 4 ] && [ -s "$ckpt" ] && [ "$count" -lt "$max" ]; then
    echo resubmit
  else
    if [ "$rc" -eq 4 ] && [ "$count" -ge "$max" ]; then
      echo "rtmini: restart chain reached RTMINI_CHAIN_MAX=$max segments; giving up" >&2
    elif [ "$rc" -eq 4 ]; then
      echo "rtmini: exit 4 but no checkpoint $ckpt; giving up" >&2
    fi
    echo fail
  fi
}

# rtmini_mpirun_launcher RANKS THREADS: fill RTMINI_LAUNCH with an mpirun line
# for this machine; --oversubscribe when ranks x threads exceed the cores.
rtmini_mpirun_launcher() {
  local ranks=$1 threads=$2 cores
  cores=$(nproc)
  export OMP_NUM_THREADS=$threads OMP_PROC_BIND=${OMP_PROC_BIND:-false}
  if [ "$(id -u)" -eq 0 ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
  fi
  RTMINI_LAUNCH=(mpirun -np "$ranks" -x OMP_NUM_THREADS -x OMP_PROC_BIND)
  if [ $((ranks * threads)) -gt "$cores" ]; then
    RTMINI_LAUNCH+=(--oversubscribe --bind-to none)
  fi
}

# rtmini_python_tool TOOL ARGS...: run an rtmini_analysis CLI with $RTMINI_PYTHON.
rtmini_python_tool() {
  local tool=$1
  shift
  PYTHONPATH="$RTMINI_ROOT/analysis${PYTHONPATH:+:$PYTHONPATH}" "${RTMINI_PYTHON:-python3}" -m "rtmini_analysis.$tool" "$@"
}
