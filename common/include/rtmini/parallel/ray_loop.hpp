#pragma once
// The policy of a loop over rays (or packets of rays), whose costs differ by orders of magnitude
// from one index to the next. On host backends the indices go out in dynamically scheduled
// chunks, as the mini-apps' trace loops and Embree's TBB loops hand out theirs: a static split
// gives each thread a fixed half, and whenever one core runs slower (a shared VM's stolen time,
// another job) the other thread idles at the end. Measured on the 2-core VM (results/bvh/README.md,
// 2026-11-29): dragon AO went from 0.79 to 0.95 of Embree's rate in wall time. Devices keep the
// plain range: their hardware schedules the warps.
#include <Kokkos_Core.hpp>
#include <type_traits>

namespace rtmini {

template <class ExecSpace>
inline constexpr bool kRunsOnHost =
    Kokkos::SpaceAccessibility<Kokkos::HostSpace, typename ExecSpace::memory_space>::accessible;

template <class ExecSpace>
using RayLoopPolicy =
    std::conditional_t<kRunsOnHost<ExecSpace>,
                       Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>,
                       Kokkos::RangePolicy<ExecSpace>>;

}  // namespace rtmini
