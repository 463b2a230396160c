#!/usr/bin/env bash
# Registers, spills and stack of sketchtrace's render kernel per instantiation, from ptxas,
# without a GPU: compiles one translation unit holding renderer.cpp's PixelKernel (extracted
# from SRC) launched for the given feature masks (kernel_features.hpp), for sm_90.
#   bash ptxas_probe.sh SRC KOKKOS_CUDA_ROOT OUTDIR FEATURES...
# SRC: a source tree (a checkout, or an unpacked `git archive` of another commit);
# KOKKOS_CUDA_ROOT: a Kokkos CUDA install (nvcc_wrapper in its bin/, nvcc on PATH).
# Prints ptxas's "Function properties" (stack frame, spill stores/loads) and register lines,
# the kernels renamed KERNEL<mask>; the full log is OUTDIR/ptxas.log.
set -euo pipefail
src=$1 kokkos=$2 dir=$3
shift 3
mkdir -p "$dir"
tu=$dir/probe.cpp
{
  echo '#include "renderer.hpp"'
  echo 'namespace rtmini::sketch {'
  awk '/^template <unsigned kFeatures>$/{buf=$0; next}
       buf!="" && /^struct PixelKernel/{p=1; print buf}
       {if(p) print; if(p && /^};/) p=0; buf=""}' "$src/miniapps/sketchtrace/renderer.cpp"
  cat << 'EOT'
template <unsigned F>
void probe_launch(const DeviceScene& sc, const DeviceCamera& cam, const TraceParams& p,
                  const StencilParams& st, const Kokkos::View<std::int64_t*, MemSpace>& px,
                  const Kokkos::View<PixelResult*, MemSpace>& out) {
  PixelKernel<F> k{{sc, cam, p}, st, false, px, out};
  using Policy = Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace, Kokkos::Schedule<Kokkos::Dynamic>,
                                     Kokkos::IndexType<std::int64_t>>;
  Kokkos::parallel_for("probe", Policy(0, 1), k);
}
EOT
  for f in "$@"; do
    echo "template void probe_launch<$f>(const DeviceScene&, const DeviceCamera&, const TraceParams&,"
    echo "  const StencilParams&, const Kokkos::View<std::int64_t*, MemSpace>&,"
    echo "  const Kokkos::View<PixelResult*, MemSpace>&);"
  done
  echo '}'
} > "$tu"
"$kokkos/bin/nvcc_wrapper" -DRTMINI_HAVE_PNG -I"$src/miniapps/sketchtrace" -I"$src/common/include" \
  -isystem "$kokkos/include" -O3 -DNDEBUG -ffp-contract=off -extended-lambda -arch=sm_90 \
  -std=c++17 -Xptxas -v -c "$tu" -o "$dir/probe.o" 2> "$dir/ptxas.log"
grep -E "Function properties|stack frame|registers" "$dir/ptxas.log" |
  sed -E 's/_ZN6Kokkos4Impl36cuda_parallel_launch_constant_memoryINS0_11ParallelForIN6rtmini6sketch11PixelKernelILj([0-9]+)E.*/KERNEL<\1>/' |
  grep -v "ViewValueFunctor\|ViewCopy\|EmptyKernel"
