#pragma once
// Every ray's closest hit and any-hit answer through one accelerator (a BVH layout or brute
// force): what the oracle tests compare, layout against layout.
#include "rtmini/bvh/traverse.hpp"
#include "test_space.hpp"

namespace rtmini::test {

struct Answers {
  Kokkos::View<Hit*, TestMemSpace> hit;
  Kokkos::View<int*, TestMemSpace> any;
};

template <class Accel>
Answers trace_all(const Accel& accel, Kokkos::View<Ray*, TestMemSpace> rays) {
  const int n = static_cast<int>(rays.extent(0));
  Answers a{Kokkos::View<Hit*, TestMemSpace>("hit", n), Kokkos::View<int*, TestMemSpace>("any", n)};
  Kokkos::parallel_for(
      "test::trace_all", Kokkos::RangePolicy<TestExecSpace>(0, n), KOKKOS_LAMBDA(int i) {
        a.hit(i) = bvh::closest_hit(accel, rays(i));
        a.any(i) = bvh::any_hit(accel, rays(i));
      });
  return a;
}

}  // namespace rtmini::test
