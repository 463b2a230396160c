#pragma once
// One entry point for both builders.
#include <vector>

#include "rtmini/bvh/build_lbvh.hpp"
#include "rtmini/bvh/build_sah.hpp"

namespace rtmini::bvh {

template <class ExecSpace, class MemorySpace = typename ExecSpace::memory_space>
Bvh<MemorySpace> build(const ExecSpace& space, Kokkos::View<const Triangle*, MemorySpace> tris,
                       BuildQuality quality) {
  if (quality == BuildQuality::kLbvh) return build_lbvh<ExecSpace, MemorySpace>(space, tris);
  Kokkos::Profiling::pushRegion("rtmini::bvh::build_sah");
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tris);
  std::vector<Triangle> v(host.data(), host.data() + host.extent(0));
  auto out = upload<MemorySpace>(build_sah_host(v), BuildQuality::kSah);
  Kokkos::Profiling::popRegion();
  return out;
}

inline const char* to_string(BuildQuality q) { return q == BuildQuality::kLbvh ? "lbvh" : "sah"; }

}  // namespace rtmini::bvh
