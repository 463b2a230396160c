#!/usr/bin/env bash
# Registers and spills of the LBVH hierarchy kernel (and the rest of build_lbvh / build_ploc) for
# sm_90, without a GPU: compiles one translation unit instantiating both builders on Kokkos::Cuda.
#   bash ptxas_probe.sh SRC KOKKOS_CUDA_ROOT OUTDIR
# SRC: a source tree (a checkout, or an unpacked `git archive <commit> common/include`);
# KOKKOS_CUDA_ROOT: a Kokkos 4 CUDA install (nvcc_wrapper in its bin/, nvcc on PATH).
set -euo pipefail
src=$1 kokkos=$2 dir=$3
mkdir -p "$dir"
cat > "$dir/probe.cpp" << 'EOT'
#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/bvh/build_ploc.hpp"
namespace rtmini::bvh {
template Bvh<Kokkos::CudaSpace> build_lbvh<Kokkos::Cuda, Kokkos::CudaSpace>(
    const Kokkos::Cuda&, Kokkos::View<const Triangle*, Kokkos::CudaSpace>, LbvhPhaseTimes*);
template Bvh<Kokkos::CudaSpace> build_ploc<Kokkos::Cuda, Kokkos::CudaSpace>(
    const Kokkos::Cuda&, Kokkos::View<const Triangle*, Kokkos::CudaSpace>, PlocPhaseTimes*);
}
EOT
NVCC_WRAPPER_DEFAULT_COMPILER=${NVCC_WRAPPER_DEFAULT_COMPILER:-g++} "$kokkos/bin/nvcc_wrapper" \
  -I"$src/common/include" -isystem "$kokkos/include" -O3 -DNDEBUG -ffp-contract=off \
  -extended-lambda -expt-relaxed-constexpr -arch=sm_90 -std=c++17 -Xptxas -v \
  -c "$dir/probe.cpp" -o "$dir/probe.o" 2> "$dir/ptxas.log"
# The hierarchy kernel's lines (its mangled name holds build_hierarchy).
awk '/Compiling entry function/{h = /build_hierarchy/} h && /registers|spill/' "$dir/ptxas.log"
