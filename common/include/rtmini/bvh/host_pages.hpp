#pragma once
// Host arrays of the CPU traversal's tree on 2 MiB pages where Linux grants them.
//
// Incoherent rays (AO, diffuse) touch node and leaf data all over the tree: with 4 KiB pages the
// dragon's 6.7 MiB wide tree spans ~1,700 pages, more than the first-level TLB holds, so a
// traversal step can wait on a page walk as well as on the cache miss. Asking for transparent
// huge pages (madvise, before the first touch) maps the same arrays with a few dozen entries.
// Embree does the same for its tree. Where huge pages are off or unknown the advice is a no-op
// and the arrays behave as plain views.
#include <cstddef>
#include <cstdint>
#include <string>
#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "rtmini/kokkos_compat.hpp"

namespace rtmini::bvh {

inline constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;
// Smaller arrays stay on plain pages: padding them to a whole huge page would waste more
// memory than the page walks they save.
inline constexpr std::size_t kHugePageMinBytes = std::size_t(1) << 20;

// An uninitialised host view of n elements; from kHugePageMinBytes on, a subview of a larger
// allocation whose elements lie in whole huge pages advised to be backed as such.
// Callers must write every element after this returns (the first touch takes the page).
template <class T, class MemorySpace>
Kokkos::View<T*, MemorySpace> huge_page_view(const char* label, std::size_t n) {
  const auto alloc = [&](std::size_t count) {
    return Kokkos::View<T*, MemorySpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string(label)), count);
  };
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  const std::size_t bytes = n * sizeof(T);
  if (bytes < kHugePageMinBytes) return alloc(n);
  // The elements start at the first element boundary at or after the first huge-page boundary
  // of a larger allocation (so within sizeof(T) of it), and whole huge pages from that boundary
  // cover them.
  const std::size_t pages = (bytes + sizeof(T) + kHugePageBytes - 1) / kHugePageBytes;
  const std::size_t padded = ((pages + 1) * kHugePageBytes + sizeof(T) - 1) / sizeof(T);
  auto whole = alloc(padded);
  const auto addr = reinterpret_cast<std::uintptr_t>(whole.data());
  const std::size_t boundary = (kHugePageBytes - addr % kHugePageBytes) % kHugePageBytes;
  const std::size_t skip = (boundary + sizeof(T) - 1) / sizeof(T);
  madvise(reinterpret_cast<void*>(addr + boundary), pages * kHugePageBytes, MADV_HUGEPAGE);
  return Kokkos::subview(whole, std::make_pair(skip, skip + n));
#else
  return alloc(n);
#endif
}

}  // namespace rtmini::bvh
