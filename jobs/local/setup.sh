#!/usr/bin/env bash
# Idempotent set-up for rtmini on Debian 12: Debian packages, then (only if no
# usable Kokkos is found) Kokkos 3.4.01 from Debian's Trilinos source package,
# built with OpenMP + Serial into the ignored prefix .deps/kokkos.
# Usage: jobs/local/setup.sh            (re-running is cheap: finished steps are skipped)
# Env:   RTMINI_SKIP_APT=1              skip apt (packages already there)
#        Kokkos_ROOT=/path              use this Kokkos (e.g. Spack 4.x with CUDA) instead
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
deps="$root/.deps"
mkdir -p "$deps"

packages=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  openmpi-bin libopenmpi-dev libhdf5-openmpi-dev hdf5-tools libxxhash-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libtomlplusplus-dev libtinyobjloader-dev nlohmann-json3-dev
  librandom123-dev libeigen3-dev libpng-dev libopenexr-dev libtinygltf-dev
  libembree-dev
  python3 python3-numpy python3-matplotlib python3-h5py python3-pytest
  shellcheck clang-format clang clang-tidy libfuzzer-14-dev
  slurm-wlm munge
  nodejs chromium
)

sudo_if_needed() { if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi; }

if [ "${RTMINI_SKIP_APT:-0}" != 1 ]; then
  missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}" >&2
    sudo_if_needed apt-get update -qq
    sudo_if_needed env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
fi

# A user's Kokkos wins: an explicit Kokkos_ROOT, or one CMake already finds.
kokkos_usable() {
  local probe="$deps/kokkos-probe"
  rm -rf "$probe" && mkdir -p "$probe"
  cat >"$probe/CMakeLists.txt" <<'CM'
cmake_minimum_required(VERSION 3.16)
project(probe CXX)
find_package(Kokkos REQUIRED)
if(NOT (Kokkos_ENABLE_OPENMP OR Kokkos_ENABLE_CUDA OR Kokkos_ENABLE_THREADS))
  message(FATAL_ERROR "Kokkos has no parallel backend")
endif()
CM
  cmake -S "$probe" -B "$probe/b" ${1:+-DKokkos_ROOT="$1"} >/dev/null 2>&1
}

prefix="$deps/kokkos"
if [ -n "${Kokkos_ROOT:-}" ]; then
  kokkos_usable "$Kokkos_ROOT" || { echo "setup: Kokkos_ROOT=$Kokkos_ROOT is not a usable Kokkos" >&2; exit 3; }
  echo "setup: using Kokkos at $Kokkos_ROOT" >&2
elif [ -f "$prefix/.rtmini-built" ]; then
  echo "setup: Kokkos already built in $prefix" >&2
elif kokkos_usable ""; then
  echo "setup: using the Kokkos that CMake finds on this system" >&2
else
  echo "setup: building Kokkos 3.4.01 (OpenMP+Serial) from Debian's trilinos source" >&2
  work="$deps/trilinos-src"
  mkdir -p "$work/lists/partial" "$work/archives/partial"
  # deb-src entry scoped to this script: a private source list and list dir.
  echo "deb-src http://deb.debian.org/debian bookworm main" >"$work/sources.list"
  aptopts=(-o Dir::Etc::SourceList="$work/sources.list" -o Dir::Etc::SourceParts=/dev/null
           -o Dir::State::Lists="$work/lists" -o Dir::Cache::Archives="$work/archives"
           -o APT::Sandbox::User=root)
  shopt -s nullglob
  tarballs=("$work"/trilinos_*.orig.tar.*)
  if [ ${#tarballs[@]} -eq 0 ]; then
    apt-get "${aptopts[@]}" update -qq
    (cd "$work" && apt-get "${aptopts[@]}" source --download-only trilinos)
    tarballs=("$work"/trilinos_*.orig.tar.*)
  fi
  tarball=${tarballs[0]}
  rm -rf "$work/src" && mkdir -p "$work/src"
  tar -xf "$tarball" -C "$work/src" --wildcards '*/packages/kokkos/*'
  ksrc=$(dirname "$(find "$work/src" -maxdepth 4 -path '*/packages/kokkos/CMakeLists.txt' | head -n1)")
  cmake -S "$ksrc" -B "$work/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" \
    -DCMAKE_CXX_STANDARD=17 -DKokkos_ENABLE_OPENMP=ON -DKokkos_ENABLE_SERIAL=ON \
    -DKokkos_ENABLE_TESTS=OFF -DKokkos_ENABLE_EXAMPLES=OFF -DBUILD_SHARED_LIBS=OFF \
    -DCMAKE_POSITION_INDEPENDENT_CODE=ON >/dev/null
  cmake --build "$work/build" -j "$(nproc)" >/dev/null
  cmake --install "$work/build" >/dev/null
  touch "$prefix/.rtmini-built"
  rm -rf "$work/src" "$work/build"
  echo "setup: Kokkos installed in $prefix" >&2
fi

# The web viewer's test dependencies (three.js, playwright-core) from npm, pinned by its lockfile.
viewer="$root/miniapps/bake/viewer"
if [ -f "$viewer/package-lock.json" ] && command -v npm >/dev/null 2>&1; then
  if [ ! -d "$viewer/node_modules" ] || [ "$viewer/package-lock.json" -nt "$viewer/node_modules" ]; then
    echo "setup: npm ci in miniapps/bake/viewer" >&2
    (cd "$viewer" && npm ci --no-audit --no-fund --loglevel=error) && touch "$viewer/node_modules"
  fi
fi
