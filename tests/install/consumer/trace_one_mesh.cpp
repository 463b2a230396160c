// Traces rays against the installed Cornell box through rtmini's BVH and checks every answer
// against the brute-force reference: proof that the installed headers, libraries and
// dependencies work together from another project. Exit 0 when all agree.
#include <cstdio>

#include "rtmini/bvh/brute_force.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "rtmini/scene/device_mesh.hpp"

namespace {

using rtmini::Real;
using Space = Kokkos::DefaultExecutionSpace;
using Memory = Space::memory_space;

// Rays from the middle of the box in uniformly distributed directions; the box is open at the
// front, so most of them, not all, hit a wall.
Kokkos::View<rtmini::Ray*, Memory> rays_from(const rtmini::Vec3 origin, int n) {
  Kokkos::View<rtmini::Ray*, Memory> rays("consumer::rays", n);
  Kokkos::parallel_for(
      "consumer::rays", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        const rtmini::Rng rng(11, std::uint64_t(i), 0);
        rtmini::Ray r;
        r.org = origin;
        r.dir = rtmini::uniform_sphere(rng.uniform(0), rng.uniform(1));
        r.tmin = 0;
        r.tmax = Real(1e30);
        rays(i) = r;
      });
  return rays;
}

// Number of rays whose BVH answer differs from the brute-force one; `hits` counts valid hits.
int count_disagreements(const rtmini::DeviceMesh<Memory>& mesh,
                        Kokkos::View<rtmini::Ray*, Memory> rays, int& hits) {
  const auto bvh = mesh.accel;  // built by upload_mesh
  const rtmini::bvh::BruteForce<Memory> reference{mesh.tris};
  int wrong = 0;
  hits = 0;
  Kokkos::parallel_reduce(
      "consumer::trace", Kokkos::RangePolicy<Space>(0, int(rays.extent(0))),
      KOKKOS_LAMBDA(int i, int& w, int& h) {
        const rtmini::Hit a = rtmini::bvh::closest_hit(bvh, rays(i));
        const rtmini::Hit b = rtmini::bvh::closest_hit(reference, rays(i));
        w += (a.prim != b.prim || a.t != b.t) ? 1 : 0;
        h += b.valid() ? 1 : 0;
      },
      wrong, hits);
  return wrong;
}

}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  const rtmini::Mesh box = rtmini::read_mesh(RTMINI_CONSUMER_MESH);
  const auto mesh = rtmini::upload_mesh<Space>(box, rtmini::bvh::BuildQuality::kLbvh);
  const int n = 4096;
  int hits = 0;
  const int wrong = count_disagreements(mesh, rays_from(rtmini::Vec3(0, 1, 0), n), hits);
  std::printf("consumer: %d triangles, %d rays, %d hits, %d disagree with brute force\n",
              int(mesh.tris.extent(0)), n, hits, wrong);
  return (wrong == 0 && hits > n / 2) ? 0 : 1;
}
