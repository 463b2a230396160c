#pragma once
// The one place where differences between Kokkos 3.4 (Debian, CPU) and Kokkos 4.x
// (CUDA) are bridged. Everything else includes this instead of spelling versions.
//
// RTMINI_NO_KOKKOS: host-only translation units (the TOML scene reader, whose
// library nvcc cannot parse) are compiled by the plain host compiler without
// Kokkos; they still share Vec3/Mesh through the fallbacks below.
#ifdef RTMINI_NO_KOKKOS
#include <cmath>
#include <cstdint>
#include <cstring>
#ifndef KOKKOS_INLINE_FUNCTION
#define KOKKOS_INLINE_FUNCTION inline
#define KOKKOS_FUNCTION
#endif
namespace rtmini::compat {
template <class To, class From>
inline To bit_cast(const From& from) {
  static_assert(sizeof(To) == sizeof(From), "bit_cast needs equal sizes");
  To to;
  std::memcpy(&to, &from, sizeof(To));
  return to;
}
}  // namespace rtmini::compat
namespace rtmini::math {
using std::acos;
using std::asin;
using std::atan;
using std::atan2;
using std::ceil;
using std::cos;
using std::exp;
using std::fabs;
using std::floor;
using std::fmax;
using std::fmin;
using std::log;
using std::log2;
using std::pow;
using std::sin;
using std::sqrt;
using std::tan;
}  // namespace rtmini::math
#else
#include <Kokkos_Core.hpp>
#include <Kokkos_Sort.hpp>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#ifndef KOKKOS_VERSION
#error "Kokkos_Core.hpp did not define KOKKOS_VERSION"
#endif
#if defined(KOKKOS_ENABLE_CUDA) && defined(__CUDACC__)
#include <cub/device/device_radix_sort.cuh>
#include <stdexcept>
#endif

namespace rtmini::compat {

#if KOKKOS_VERSION >= 40000
inline constexpr bool kKokkos4 = true;
#else
inline constexpr bool kKokkos4 = false;
#endif

#if defined(KOKKOS_ENABLE_CUDA) && defined(__CUDACC__)
// A CUDA runtime call's error as an exception naming the call.
inline void check_cuda(cudaError_t status, const char* what) {
  if (status != cudaSuccess)
    throw std::runtime_error(std::string(what) + ": " + cudaGetErrorString(status));
}
#endif

// Sort a 1D view of keys in place on its own execution space.
// 3.4 on host spaces falls back to std::sort; 4.x on CUDA uses the vendor sort.
template <class ExecSpace, class ViewType>
void sort(const ExecSpace& space, const ViewType& view) {
#if KOKKOS_VERSION >= 40200
  Kokkos::sort(space, view);
#else
  space.fence();
  Kokkos::sort(view);
#endif
}

namespace detail {
// Kokkos 3.4 has no sort by key: each pair packed into one 64-bit key (key high, value low) in
// `packed`, sorted whole (so equal keys come out ordered by value), and unpacked.
template <class ExecSpace, class MemorySpace>
void sort_packed_pairs(const ExecSpace& space,
                       const Kokkos::View<std::uint32_t*, MemorySpace>& keys,
                       const Kokkos::View<std::uint32_t*, MemorySpace>& values,
                       const Kokkos::View<std::uint64_t*, MemorySpace>& packed) {
  const std::int64_t n = static_cast<std::int64_t>(keys.extent(0));
  using Policy = Kokkos::RangePolicy<ExecSpace, Kokkos::IndexType<std::int64_t> >;
  Kokkos::parallel_for(
      "rtmini::compat::sort_by_key::pack", Policy(space, 0, n),
      KOKKOS_LAMBDA(std::int64_t i) { packed(i) = std::uint64_t(keys(i)) << 32 | values(i); });
  sort(space, packed);
  Kokkos::parallel_for(
      "rtmini::compat::sort_by_key::unpack", Policy(space, 0, n), KOKKOS_LAMBDA(std::int64_t i) {
        keys(i) = static_cast<std::uint32_t>(packed(i) >> 32);
        values(i) = static_cast<std::uint32_t>(packed(i) & 0xffffffffu);
      });
  space.fence();
}
}  // namespace detail

// Sorts `keys` ascending on `space` and permutes `values` with them. 4.3+ has
// Kokkos::Experimental::sort_by_key (on CUDA thrust's radix sort of the 32-bit keys: half the
// passes of a 64-bit key, and stable, so equal keys keep ascending values as below); 3.4 has
// none, so the pair is packed into one 64-bit key (key high, value low) and sorted whole, which
// orders equal keys by value. Where another backend orders equal keys otherwise, the LBVH over
// them differs in shape only (traversal answers do not depend on it).
template <class ExecSpace, class MemorySpace>
void sort_by_key(const ExecSpace& space, const Kokkos::View<std::uint32_t*, MemorySpace>& keys,
                 const Kokkos::View<std::uint32_t*, MemorySpace>& values) {
#if KOKKOS_VERSION >= 40300
  Kokkos::Experimental::sort_by_key(space, keys, values);
#else
  Kokkos::View<std::uint64_t*, MemorySpace> packed(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::compat::sort_by_key"),
      keys.extent(0));
  detail::sort_packed_pairs(space, keys, values, packed);
#endif
}

// sort_by_key in storage the caller provides, for keys below 2^key_bits: keys[0] and values[0]
// hold the pairs; keys[1] and values[1] (as long) and `temp` (sort_pairs_temp_bytes) are
// scratch. Returns which half, 0 or 1, holds the sorted pairs. On CUDA this is CUB's radix sort
// of only the key bits used, ping-ponging between the halves (stable: equal keys keep their
// order), without thrust's allocation, copy back and synchronization per call; on Kokkos 3.4 the
// packed sort above in `temp`; elsewhere Kokkos' sort_by_key in place.
template <class ExecSpace>
std::size_t sort_pairs_temp_bytes(int n, int key_bits) {
#if defined(KOKKOS_ENABLE_CUDA) && defined(__CUDACC__)
  if constexpr (std::is_same_v<ExecSpace, Kokkos::Cuda>) {
    std::size_t bytes = 0;
    cub::DoubleBuffer<std::uint32_t> k(nullptr, nullptr), v(nullptr, nullptr);
    check_cuda(cub::DeviceRadixSort::SortPairs(nullptr, bytes, k, v, n, 0, key_bits),
               "cub::DeviceRadixSort::SortPairs (temporary size)");
    return bytes;
  }
#endif
  (void)key_bits;
  return KOKKOS_VERSION >= 40300 ? 0 : static_cast<std::size_t>(n) * sizeof(std::uint64_t);
}

template <class ExecSpace, class MemorySpace>
int sort_pairs(const ExecSpace& space, const Kokkos::View<std::uint32_t*, MemorySpace> (&keys)[2],
               const Kokkos::View<std::uint32_t*, MemorySpace> (&values)[2],
               const Kokkos::View<unsigned char*, MemorySpace>& temp, int key_bits) {
#if defined(KOKKOS_ENABLE_CUDA) && defined(__CUDACC__)
  if constexpr (std::is_same_v<ExecSpace, Kokkos::Cuda>) {
    const int n = static_cast<int>(keys[0].extent(0));  // 32-bit offsets: CUB's faster kernels
    cub::DoubleBuffer<std::uint32_t> k(keys[0].data(), keys[1].data());
    cub::DoubleBuffer<std::uint32_t> v(values[0].data(), values[1].data());
    std::size_t bytes = temp.extent(0);
    check_cuda(cub::DeviceRadixSort::SortPairs(temp.data(), bytes, k, v, n, 0, key_bits,
                                               space.cuda_stream()),
               "cub::DeviceRadixSort::SortPairs");
    return k.selector;
  }
#endif
  (void)key_bits;
#if KOKKOS_VERSION >= 40300
  (void)temp;
  Kokkos::Experimental::sort_by_key(space, keys[0], values[0]);
#else
  const Kokkos::View<std::uint64_t*, MemorySpace> packed(
      reinterpret_cast<std::uint64_t*>(temp.data()), keys[0].extent(0));
  detail::sort_packed_pairs(space, keys[0], values[0], packed);
#endif
  return 0;
}

// Bit-level reinterpretation usable in device code (std::bit_cast is C++20).
template <class To, class From>
KOKKOS_INLINE_FUNCTION To bit_cast(const From& from) {
  static_assert(sizeof(To) == sizeof(From), "bit_cast needs equal sizes");
  To to;
  memcpy(&to, &from, sizeof(To));
  return to;
}

// Set bits of a 64-bit word, in one instruction on both sides (Kokkos 3.4 has no
// Kokkos::Experimental::popcount; C++20's std::popcount is not device code).
KOKKOS_INLINE_FUNCTION int popcount64(std::uint64_t x) {
#ifdef __CUDA_ARCH__
  return __popcll(x);
#else
  return __builtin_popcountll(x);
#endif
}

// Whether p holds on every lane of the warp that executes this call together (CUDA: the lanes
// converged here, so a lane that left the loop or is elsewhere cannot block it); on the host,
// where a thread is its own warp, p itself. For scheduling decisions only (any_hit_gpu.hpp's
// speculative traversal): results must not depend on it.
KOKKOS_INLINE_FUNCTION bool warp_all(bool p) {
#ifdef __CUDA_ARCH__
  return __all_sync(__activemask(), p) != 0;
#else
  return p;
#endif
}

template <class T>
KOKKOS_INLINE_FUNCTION T kmin(T a, T b) {
  return b < a ? b : a;
}
template <class T>
KOKKOS_INLINE_FUNCTION T kmax(T a, T b) {
  return a < b ? b : a;
}

// Name of the default execution space, e.g. "OpenMP", "Cuda".
inline const char* backend_name() { return Kokkos::DefaultExecutionSpace::name(); }

inline int concurrency() {
#if KOKKOS_VERSION >= 40000
  return Kokkos::DefaultExecutionSpace().concurrency();
#else
  return Kokkos::DefaultExecutionSpace::concurrency();
#endif
}

// Whether the default memory space is separate device memory (then a run's Views count
// against the device, not the host).
inline constexpr bool kDeviceMemory =
    !Kokkos::SpaceAccessibility<Kokkos::HostSpace,
                                Kokkos::DefaultExecutionSpace::memory_space>::accessible;

// Free bytes of this rank's device, and the number of devices on the node; -1 where the
// build has no device runtime to ask (host backends: the host check covers everything).
struct DeviceMemoryInfo {
  double free_bytes = -1;
  int devices = 0;
};
inline DeviceMemoryInfo device_memory_info() {
  DeviceMemoryInfo info;
#ifdef KOKKOS_ENABLE_CUDA
  std::size_t free_bytes = 0, total_bytes = 0;
  int devices = 0;
  if (cudaMemGetInfo(&free_bytes, &total_bytes) == cudaSuccess &&
      cudaGetDeviceCount(&devices) == cudaSuccess) {
    info.free_bytes = static_cast<double>(free_bytes);
    info.devices = devices;
  }
#endif
  return info;
}

// Starts Kokkos from the program's own settings, never from argv (see
// report/common_options.hpp). Both versions still read KOKKOS_* environment variables.
// threads <= 0 leaves the host thread count to OMP_NUM_THREADS or the core count.
inline void initialize(int threads) {
#if KOKKOS_VERSION >= 40000
  Kokkos::InitializationSettings settings;
  if (threads > 0) settings.set_num_threads(threads);
  Kokkos::initialize(settings);
#else
  Kokkos::InitArguments arguments;
  if (threads > 0) arguments.num_threads = threads;
  Kokkos::initialize(arguments);
#endif
}

// Kokkos prints its option list only while it parses a command line, so hand it one that
// asks for nothing else; it is initialised and finalised again just for that.
inline void print_kokkos_help(const char* program) {
  char name[] = "rtmini";
  char flag[] = "--kokkos-help";
  char* args[] = {program ? const_cast<char*>(program) : name, flag, nullptr};
  int count = 2;
  Kokkos::initialize(count, args);
  Kokkos::finalize();
}

// Host memory the caller owns, seen as a one-dimensional View without a copy: the host side of
// a deep_copy to or from a device View. Spelled once here rather than at every transfer.
template <class T>
using HostView = Kokkos::View<T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged> >;

template <class T>
HostView<T> host_view(T* data, std::size_t n) {
  return HostView<T>(data, n);
}

// A new View in `Space` holding a copy of `host` (the label names it in Kokkos' tools).
template <class Space, class T>
Kokkos::View<T*, Space> upload(const std::string& label, const std::vector<T>& host) {
  Kokkos::View<T*, Space> out(label, host.size());
  Kokkos::deep_copy(out, host_view(host.data(), host.size()));
  return out;
}

// `to` resized to `from` and filled with its contents.
template <class T, class... Props>
void download(const Kokkos::View<T*, Props...>& from, std::vector<std::remove_const_t<T> >& to) {
  to.resize(from.extent(0));
  Kokkos::deep_copy(host_view(to.data(), to.size()), from);
}

}  // namespace rtmini::compat

// Device-callable math: Kokkos 3.4 keeps these in Kokkos::Experimental, 4.x in Kokkos.
namespace rtmini::math {
#if KOKKOS_VERSION >= 40000
using Kokkos::acos;
using Kokkos::asin;
using Kokkos::atan;
using Kokkos::atan2;
using Kokkos::ceil;
using Kokkos::cos;
using Kokkos::exp;
using Kokkos::fabs;
using Kokkos::floor;
using Kokkos::fmax;
using Kokkos::fmin;
using Kokkos::log;
using Kokkos::log2;
using Kokkos::pow;
using Kokkos::sin;
using Kokkos::sqrt;
using Kokkos::tan;
#else
using Kokkos::Experimental::acos;
using Kokkos::Experimental::asin;
using Kokkos::Experimental::atan;
using Kokkos::Experimental::atan2;
using Kokkos::Experimental::ceil;
using Kokkos::Experimental::cos;
using Kokkos::Experimental::exp;
using Kokkos::Experimental::fabs;
using Kokkos::Experimental::floor;
using Kokkos::Experimental::fmax;
using Kokkos::Experimental::fmin;
using Kokkos::Experimental::log;
using Kokkos::Experimental::log2;
using Kokkos::Experimental::pow;
using Kokkos::Experimental::sin;
using Kokkos::Experimental::sqrt;
using Kokkos::Experimental::tan;
#endif
}  // namespace rtmini::math
#endif  // RTMINI_NO_KOKKOS

namespace rtmini::math {
// Written out because 3.4 has no device isfinite/copysign; exact for IEEE types: x - x is 0
// for every finite x and NaN for an infinity or a NaN.
template <class T>
KOKKOS_INLINE_FUNCTION bool isfinite(T x) {
  return (x - x) == T(0);  // NOLINT(misc-redundant-expression): the test is x - x itself
}
KOKKOS_INLINE_FUNCTION bool signbit(float x) {
  return (compat::bit_cast<std::uint32_t>(x) >> 31) != 0u;
}
KOKKOS_INLINE_FUNCTION bool signbit(double x) {
  return (compat::bit_cast<std::uint64_t>(x) >> 63) != 0u;
}
template <class T>
KOKKOS_INLINE_FUNCTION T copysign(T mag, T sgn) {
  const T m = mag < T(0) ? -mag : mag;
  return signbit(sgn) ? -m : m;
}
template <class T>
KOKKOS_INLINE_FUNCTION T clamp(T x, T lo, T hi) {
  return x < lo ? lo : (x > hi ? hi : x);
}
inline constexpr double kPi = 3.14159265358979323846;
}  // namespace rtmini::math
