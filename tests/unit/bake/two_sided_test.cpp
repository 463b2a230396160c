// Two-sided mirrors (`bake --two-sided`): a closed, all-emissive mirror sphere (E = 1, Kr = 0.5,
// no diffuse part) seen from inside is a furnace: after K = 3 iterations every colour whose
// viewpoint looks from inside reads E (1 - Kr^4) / (1 - Kr) = 1.875. Two-sided mirrors give it
// whichever way the faces are wound. One-sided mirrors (the default) give it only when the faces
// face the inside: wound outward, a viewpoint inside is behind every vertex, is folded to the
// front, and its mirror ray leaves the sphere (reads the background, so the colour is E alone).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "chef.hpp"
#include "rtmini/sampling/fibonacci.hpp"
#include "rtmini/scene/primitives.hpp"

namespace rtmini::bake {
namespace {

constexpr int kViewpoints = 1000, kIterations = 3;
constexpr double kFurnace = 1.875;

Mesh mirror_sphere(bool inward) {
  Mesh m;
  Material mat;
  mat.diffuse = Vec3f(0.0f);  // no direct light: base = emission alone
  mat.reflective = Vec3f(0.5f);
  mat.emissive = Vec3f(1.0f);
  m.materials.push_back(mat);
  append_icosphere(m, Vec3d(0.0), 1.0, 2, 0, 0);
  if (inward)
    for (Face& f : m.faces) std::swap(f.v[1], f.v[2]);
  return m;
}

// The largest |colour - furnace value| over every vertex and every viewpoint that looks at it
// from inside, within 37 degrees of the radius (so the ~8 viewpoints a lookup blends, within
// K lookups, never reach a viewpoint from outside).
double worst_inside_error(bool inward, bool two_sided) {
  const Mesh mesh = mirror_sphere(inward);
  BakeConfig c;
  c.viewpoints = kViewpoints;
  c.iterations = kIterations;
  c.shadow_samples = 1;
  c.two_sided = two_sided;
  const BakeSceneHost host = prepare_bake_scene(mesh, kViewpoints);
  const BakeSceneDevice s = upload_bake_scene(mesh, host, kViewpoints, bvh::BuildQuality::kSah);
  const std::int64_t nv = host.vertices();
  Chef chef(s, c, host.colors());
  chef.bake_base(0, nv);
  Kokkos::View<Vec3f*, MemSpace> maps[2] = {Kokkos::View<Vec3f*, MemSpace>("map0", host.colors()),
                                            Kokkos::View<Vec3f*, MemSpace>("map1", host.colors())};
  chef.bake_iteration(0, 0, nv, 0, HitCacheMode::kOff, maps[0], maps[0]);
  for (int it = 1; it <= kIterations; ++it)
    chef.bake_iteration(it, 0, nv, 0, HitCacheMode::kOff, maps[(it - 1) % 2], maps[it % 2]);
  const int last = kIterations % 2;
  chef.to_viewpoint_order(0, nv, maps[last], maps[1 - last]);  // read below by viewpoint index
  const auto map = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), maps[1 - last]);
  double worst = 0, lo = 1e30, hi = -1e30;
  std::int64_t checked = 0;
  for (std::int64_t v = 0; v < nv; ++v) {
    EXPECT_EQ(host.color_offset[v + 1] - host.color_offset[v], kViewpoints);
    const Vec3d out = normalize(mesh.positions[v]);
    for (int i = 0; i < kViewpoints; ++i) {
      if (dot(Vec3d(fibonacci_point(i, kViewpoints)), out) < 0.8) continue;  // camera inside
      const Vec3f col = map(host.color_offset[v] + i);
      worst = std::max(worst, double(std::fabs(col.x - kFurnace)));
      lo = std::min(lo, double(col.x));
      hi = std::max(hi, double(col.x));
      ++checked;
    }
  }
  EXPECT_GT(checked, nv * kViewpoints / 20);
  std::printf(
      "%s, %s-sided: worst |colour - %.3f| = %.2e over %lld inside colours (%.6f .. %.6f)\n",
      inward ? "wound inward" : "wound outward", two_sided ? "two" : "one", kFurnace, worst,
      static_cast<long long>(checked), lo, hi);
  return worst;
}

TEST(BakeTwoSided, MirrorSphereFromInsideIsAFurnaceInBothWindings) {
  EXPECT_LT(worst_inside_error(/*inward=*/true, /*two_sided=*/true), 1e-4);
  EXPECT_LT(worst_inside_error(/*inward=*/false, /*two_sided=*/true), 1e-4);
}

TEST(BakeTwoSided, OneSidedMirrorsSeeTheInsideOnlyWhenWoundInward) {
  EXPECT_LT(worst_inside_error(/*inward=*/true, /*two_sided=*/false), 1e-4);
  // Outward: every inside colour is E = 1 (the mirror rays leave), 0.875 off.
  EXPECT_NEAR(worst_inside_error(/*inward=*/false, /*two_sided=*/false), kFurnace - 1.0, 1e-4);
}

}  // namespace
}  // namespace rtmini::bake
