#pragma once
// Direct illumination with shadow rays: quad area lights and emissive meshes with
// stratified jittered samples (the hand-drawn seed's soft shadows; the
// distribution seed's jittered light sub-sections), and point lights.
#include "rtmini/bvh/shaft.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/sampling/rng.hpp"
#include "shading.hpp"
#include "stratify.hpp"

namespace rtmini::sketch {

// Rays traced and (with stats) ray-triangle tests, per pixel.
struct TraceCounter {
  std::uint32_t rays = 0;
  std::uint64_t tests = 0;  // ray-triangle tests (with stats)
  std::uint64_t nodes = 0;  // BVH nodes visited (with stats)
  bool stats = false;
};

template <class Accel>
KOKKOS_INLINE_FUNCTION Hit trace_closest(const Accel& accel, const Ray& ray, TraceCounter& c) {
  ++c.rays;
  if (c.stats) {
    bvh::TraversalStats st;
    const Hit h = bvh::closest_hit(accel, ray, st);
    c.tests += st.tests;
    c.nodes += st.nodes;
    return h;
  }
  return bvh::closest_hit(accel, ray);
}

template <class Accel>
KOKKOS_INLINE_FUNCTION bool trace_occluded(const Accel& accel, const Ray& ray, TraceCounter& c) {
  ++c.rays;
  if (c.stats) {
    bvh::TraversalStats st;
    const bool h = bvh::any_hit(accel, ray, st);
    c.tests += st.tests;
    c.nodes += st.nodes;
    return h;
  }
  return bvh::any_hit(accel, ray);
}

// Whole-scene queries at the ray's instant. These trace the still BVH only; motion_trace.hpp
// overloads them for scenes with moving objects (MovingScene, found by argument-dependent
// lookup where the kernels instantiate), so a still scene runs exactly the code above.
template <class Scene>
KOKKOS_INLINE_FUNCTION Hit scene_closest(const Scene& scene, const Ray& ray, TraceCounter& c) {
  return trace_closest(scene.mesh.accel, ray, c);
}
template <class Scene>
KOKKOS_INLINE_FUNCTION bool scene_occluded(const Scene& scene, const Ray& ray, TraceCounter& c) {
  return trace_occluded(scene.mesh.accel, ray, c);
}
// Whether a moving object blocks the segment (the shaft path's complement: shafts hold still
// triangles only).
template <class Scene>
KOKKOS_INLINE_FUNCTION bool movers_occlude(const Scene&, const Ray&, TraceCounter&) {
  return false;
}
template <class Scene>
KOKKOS_INLINE_FUNCTION Surface scene_surface(const Scene& scene, const Ray& ray, const Hit& hit,
                                             bool smooth) {
  return surface_at(scene, ray, hit, smooth);
}

// How a shading point samples area lights: `samples` shadow rays per light using
// strata [first, first + samples) of `strata` strata over the light, random pair
// numbers from `pair_base`.
struct ShadowPlan {
  int samples = 1;
  int first = 0;
  int strata = 1;
  std::uint32_t pair_base = 0;
  std::uint32_t key = 0;  // per-pixel stratum permutation key
  bool soft = true;
};

// Shaft culling pays off from this many shadow rays per light and shading point.
inline constexpr int kShaftMinSamples = 8;
// A shadow ray stops this fraction of the way to its light point (the light's surface is no
// blocker); its shaft reaches a little further, so that it holds every such segment.
inline constexpr Real kShadowRayReach = Real(1 - 1e-4);
inline constexpr Real kShaftReach = Real(1 - 0.5e-4);

// Whether a shadow segment [tmin, tmax] (unit direction) is blocked by the sphere around a
// solid ball: it enters the inner ball and both of its ends lie outside the outer one.
KOKKOS_FORCEINLINE_FUNCTION bool segment_blocked_by_ball(const Ray& r, const SolidBall& b) {
  const Vec3 oc = r.org - b.center;
  const Real half_b = dot(oc, r.dir);
  const Real oc2 = dot(oc, oc);
  const Real disc = half_b * half_b - (oc2 - b.inner * b.inner);
  if (!(disc > Real(0))) return false;
  const Real s = math::sqrt(disc);
  if (!(-half_b - s < r.tmax && -half_b + s > r.tmin)) return false;
  const Real outer2 = b.outer * b.outer;
  const auto outside = [&](Real t) { return oc2 + t * (2 * half_b + t) > outer2; };  // |oc + t d|^2
  return outside(r.tmin) && outside(r.tmax);
}

// Unoccluded shadow-ray test from the surface towards point q (light geometry at q is not a
// blocker). With `blockers` (the shaft's, bvh/shaft.hpp) only those triangles are tested:
// the same answer as a traversal, for rays inside that shaft.
// `org` is the shading point's shadow-ray origin, offset_ray_origin(p, ng, bound).
template <class Scene>
KOKKOS_FORCEINLINE_FUNCTION bool visible(const Scene& scene, const Vec3& org, const Vec3& q,
                                         Real time, TraceCounter& c,
                                         const bvh::ShaftBlockers* blockers = nullptr) {
  Ray r;
  r.org = org;
  const Vec3 d = q - r.org;
  const Real dist = length(d);
  if (!(dist > Real(0))) return false;
  r.dir = d / dist;
  r.tmin = Real(0);
  r.tmax = dist * kShadowRayReach;
  r.time = time;
  if (blockers) {
    ++c.rays;
    return !bvh::any_hit_blockers(scene.mesh.accel, *blockers, r, c.stats ? &c.tests : nullptr) &&
           !movers_occlude(scene, r, c);
  }
  // A segment through a solid ball crosses its sphere's triangles: the traversal's answer.
  for (int b = 0; b < scene.num_solid_balls; ++b)
    if (segment_blocked_by_ball(r, scene.solid_balls(b))) {
      ++c.rays;
      return false;
    }
  return !scene_occluded(scene, r, c);
}

// The blockers of the shaft from the shading point's shadow-ray origin to a quad light;
// false when the shaft is degenerate or holds too many triangles (trace each ray).
template <class Scene>
KOKKOS_INLINE_FUNCTION bool quad_shaft_blockers(const Scene& scene, const Vec3& org,
                                                const QuadLight& ql, bvh::ShaftBlockers& out,
                                                TraceCounter& c) {
  bvh::Shaft shaft;
  if (!bvh::make_shaft(org, ql.corner, ql.u, ql.v, kShaftReach, shaft)) return false;
  std::uint32_t nodes = 0;
  const bool ok = bvh::collect_shaft_blockers(scene.mesh.accel, shaft, out, nodes);
  if (c.stats) c.nodes += nodes;
  return ok;
}

// Irradiance-like sum over lights of L_e cos_s cos_l A / r^2 (area lights, two-sided)
// and I cos_s / r^2 (point lights); the caller multiplies by Kd / pi.
template <class Scene>
KOKKOS_INLINE_FUNCTION Vec3 direct_irradiance(const Scene& scene, const Surface& s, const Rng& rng,
                                              const ShadowPlan& plan, TraceCounter& c) {
  Vec3 sum(Real(0));
  const int samples = plan.soft ? plan.samples : 1;
  const Real inv_samples = Real(1) / Real(samples);
  int light = 0;
  const Vec3 org = offset_ray_origin(s.p, s.ng, s.coordinate_bound);
  const bvh::ShaftBlockers* blockers = nullptr;
  auto area_sample = [&](const Vec3& q, const Vec3& nl, const Vec3& le, Real area) {
    const Vec3 w = q - s.p;
    const Real d2 = dot(w, w);
    if (!(d2 > Real(0))) return;
    const Vec3 wi = w / math::sqrt(d2);
    const Real cos_s = dot(s.ns, wi);
    const Real cos_l = math::fabs(dot(nl, wi));
    if (cos_s <= Real(0) || dot(s.ng, wi) <= Real(0) || cos_l <= Real(0)) return;
    if (!visible(scene, org, q, s.time, c, blockers)) return;
    sum += le * (cos_s * cos_l * area / d2 * inv_samples);
  };
  for (int l = 0; l < scene.num_quads; ++l, ++light) {
    const QuadLight ql = scene.quads(l);
    if (!plan.soft) {
      area_sample(ql.corner + ql.u * Real(0.5) + ql.v * Real(0.5), ql.normal, ql.emission, ql.area);
      continue;
    }
    bvh::ShaftBlockers shaft;
    blockers = samples >= kShaftMinSamples && quad_shaft_blockers(scene, org, ql, shaft, c)
                   ? &shaft
                   : nullptr;
    const StrataShape shape = strata_shape(plan.strata);
    const std::uint32_t key = plan.key ^ static_cast<std::uint32_t>(light);
    const std::uint32_t pair0 = plan.pair_base + static_cast<std::uint32_t>(light * samples);
    // Consecutive pairs share one Philox block (Rng::uniform2 draws the same numbers).
    r123::Philox4x32::ctr_type block{};
    std::uint32_t block_id = ~0u;
    for (int j = 0; j < samples; ++j) {
      const std::uint32_t pair = pair0 + static_cast<std::uint32_t>(j);
      if ((pair >> 1) != block_id) {
        block_id = pair >> 1;
        block = rng.block(block_id);
      }
      const unsigned o = (pair & 1u) * 2u;
      Real x, y;
      stratum_2d(plan.first + j, plan.strata, shape, key, Real(Rng::to_unit(block.v[o])),
                 Real(Rng::to_unit(block.v[o + 1])), x, y);
      area_sample(ql.corner + ql.u * x + ql.v * y, ql.normal, ql.emission, ql.area);
    }
    blockers = nullptr;
  }
  for (int l = 0; l < scene.num_mesh_lights; ++l, ++light) {
    const MeshLight ml = scene.mesh_lights(l);
    for (int j = 0; j < samples; ++j) {
      float a, b;
      rng.uniform2(plan.pair_base + static_cast<std::uint32_t>(light * samples + j), a, b);
      Real x = a, y = b;
      if (plan.soft)
        stratum_2d(plan.first + j, plan.strata, plan.key ^ static_cast<std::uint32_t>(light),
                   Real(a), Real(b), x, y);
      // Pick a triangle by area with x (binary search of the CDF), reuse x's
      // position inside that triangle's CDF interval as the first barycentric number.
      int lo = ml.first, hi = ml.first + ml.count - 1;
      while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (scene.emissive_cdf(mid) > x)
          hi = mid;
        else
          lo = mid + 1;
      }
      const Real c0 = lo == ml.first ? Real(0) : scene.emissive_cdf(lo - 1);
      const Real c1 = scene.emissive_cdf(lo);
      const Real r1 = below_one(c1 > c0 ? (x - c0) / (c1 - c0) : Real(0.5));
      const int tri = scene.emissive_tris(lo);
      const Triangle& t = scene.mesh.tris(tri);
      Real bu, bv;
      uniform_triangle(r1, y, bu, bv);
      const Vec3 q = barycentric_point(t.a, t.b, t.c, bu, bv);
      const Vec3 le = scene.mesh.materials(scene.mesh.tri_material(tri)).emissive;
      area_sample(q, triangle_normal(t.a, t.b, t.c), le, ml.area);
    }
  }
  for (int l = 0; l < scene.num_points; ++l) {
    const PointLight pl = scene.points(l);
    const Vec3 w = pl.position - s.p;
    const Real d2 = dot(w, w);
    if (!(d2 > Real(0))) continue;
    const Vec3 wi = w / math::sqrt(d2);
    const Real cos_s = dot(s.ns, wi);
    if (cos_s <= Real(0) || dot(s.ng, wi) <= Real(0)) continue;
    if (!visible(scene, org, pl.position, s.time, c)) continue;
    sum += pl.intensity * (cos_s / d2);
  }
  return sum;
}

}  // namespace rtmini::sketch
