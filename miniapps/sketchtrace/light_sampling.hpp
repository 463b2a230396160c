#pragma once
// Direct illumination with shadow rays: quad area lights and emissive meshes with
// stratified jittered samples (the hand-drawn seed's soft shadows; the
// distribution seed's jittered light sub-sections), and point lights.
#include "kernel_features.hpp"
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

// How a shading point samples area lights: `samples` shadow rays per light, random pair
// numbers from `pair_base`. Joint stratification: the `pixel_strata` pixel samples of a pixel
// that share this plan split each light into pixel_strata x samples strata, in `samples`
// blocks of pixel_strata consecutive strata, and this pixel sample takes stratum
// (pixel_cell + j) mod pixel_strata of block j. So the pixel's shadow rays fall one in each
// stratum (4 spp x 4 shadow samples covers the light like 16 x 1) and each pixel sample's own
// rays fall in different blocks (rows of the strata grid).
struct ShadowPlan {
  int samples = 1;
  int pixel_strata = 1;
  int pixel_cell = 0;
  std::uint32_t pair_base = 0;
  std::uint32_t key = 0;  // per-pixel stratum permutation key
  bool soft = true;
};

// Sample j of a plan's light strata, jittered by (u1, u2): a point in [0,1)^2. `shape` is
// strata_shape(plan.samples * plan.pixel_strata); `cell` is (pixel_cell + j) mod pixel_strata,
// which the caller's loop over j steps (first_cell, next_cell): an integer modulo per shadow
// ray costs a GPU dozens of instructions. With one pixel sample (or one shadow sample) this is
// stratum j (or pixel_cell) of the plan's strata, as before joint stratification.
KOKKOS_FORCEINLINE_FUNCTION void light_stratum(const ShadowPlan& plan, int j, int cell,
                                               StrataShape shape, std::uint32_t key, Real u1,
                                               Real u2, Real& x, Real& y) {
  const int n = plan.pixel_strata;
  stratum_2d(j * n + cell, plan.samples * n, shape, key, u1, u2, x, y);
}
KOKKOS_FORCEINLINE_FUNCTION int first_cell(const ShadowPlan& plan) {
  return plan.pixel_cell % plan.pixel_strata;
}
KOKKOS_FORCEINLINE_FUNCTION int next_cell(const ShadowPlan& plan, int cell) {
  return cell + 1 == plan.pixel_strata ? 0 : cell + 1;
}

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

// A quad light's rectangle as seen from a point, for sampling it by solid angle (Urena,
// Fajardo & King 2013, "An area-preserving parametrization for spherical rectangles"):
// frame x, y along the edges and z away from the point's side, the rectangle's extent
// [x0, x1] x [y0, y1] at depth z0 < 0 in that frame, and the solid angle it subtends.
struct SphericalRect {
  Vec3 o, x, y, z;
  Real x0 = 0, x1 = 0, y0 = 0, y1 = 0, z0 = 0;
  Real b0 = 0, b1 = 0, k = 0;
  Real solid_angle = 0;
};

// Below this solid angle (steradians) a quad light is sampled by area: the angle sum
// g0 + g1 + g2 + g3 - 2 pi loses float digits as it shrinks, and area sampling is already
// nearly exact there (cosines and distance hardly vary over the light).
inline constexpr Real kMinSolidAngle = Real(1e-2);
// Edges whose directions' cosine exceeds this are not a rectangle: area sampling.
inline constexpr Real kRectangleSkew = Real(1e-4);

// Whether the quad light seen from `o` is sampled by solid angle (then `r` is filled).
KOKKOS_INLINE_FUNCTION bool spherical_rect(const QuadLight& ql, const Vec3& o, SphericalRect& r) {
  const Real eu = length(ql.u), ev = length(ql.v);
  if (!(eu > Real(0) && ev > Real(0))) return false;
  r.x = ql.u / eu;
  r.y = ql.v / ev;
  if (math::fabs(dot(r.x, r.y)) > kRectangleSkew) return false;
  r.z = cross(r.x, r.y);
  const Vec3 d = ql.corner - o;
  r.z0 = dot(d, r.z);
  if (r.z0 > Real(0)) {
    r.z = -r.z;
    r.z0 = -r.z0;
  }
  r.o = o;
  r.x0 = dot(d, r.x);
  r.y0 = dot(d, r.y);
  r.x1 = r.x0 + eu;
  r.y1 = r.y0 + ev;
  // Inner normals of the four planes through o and the rectangle's edges, and the angles
  // between them; the solid angle is their sum less 2 pi (Girard).
  const Vec3 n0 = normalize(Vec3(Real(0), r.z0, -r.y0));
  const Vec3 n1 = normalize(Vec3(-r.z0, Real(0), r.x1));
  const Vec3 n2 = normalize(Vec3(Real(0), -r.z0, r.y1));
  const Vec3 n3 = normalize(Vec3(r.z0, Real(0), -r.x0));
  const auto angle = [](const Vec3& a, const Vec3& b) {
    return math::acos(math::clamp(-dot(a, b), Real(-1), Real(1)));
  };
  const Real g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
  r.b0 = n0.z;
  r.b1 = n2.z;
  r.k = Real(2 * math::kPi) - g2 - g3;
  r.solid_angle = g0 + g1 - r.k;
  return r.solid_angle > kMinSolidAngle;
}

// The point of the rectangle at (u, v) in [0,1)^2 under the area-preserving map from the
// unit square to its spherical rectangle: uniform (u, v) give directions of pdf 1/solid_angle.
KOKKOS_INLINE_FUNCTION Vec3 spherical_rect_point(const SphericalRect& r, Real u, Real v) {
  // u picks the x of the point through the sub-rectangle of solid angle u * solid_angle.
  const Real au = u * r.solid_angle + r.k;
  const Real fu = (math::cos(au) * r.b0 - r.b1) / math::sin(au);
  const Real cu = math::clamp(math::copysign(Real(1), fu) / math::sqrt(fu * fu + r.b0 * r.b0),
                              Real(-1), Real(1));
  const Real sin_u = math::sqrt(math::fmax(Real(1) - cu * cu, Real(1e-12)));
  const Real xu = math::clamp(-(cu * r.z0) / sin_u, r.x0, r.x1);
  // v picks y uniformly in the projected height h = y / |(xu, y, z0)|.
  const Real dd = math::sqrt(xu * xu + r.z0 * r.z0);
  const Real h0 = r.y0 / math::sqrt(dd * dd + r.y0 * r.y0);
  const Real h1 = r.y1 / math::sqrt(dd * dd + r.y1 * r.y1);
  const Real hv = h0 + v * (h1 - h0);
  const Real hv2 = hv * hv;
  const Real yv = hv2 < Real(1) - Real(1e-6)
                      ? math::clamp(hv * dd / math::sqrt(Real(1) - hv2), r.y0, r.y1)
                      : r.y1;
  return r.o + r.x * xu + r.y * yv + r.z * r.z0;
}

// Solid-angle pdf with which a shading point at p samples quad light `ql` towards q on it
// (the light's unit normal nl; q - p of squared length d2): 1/solid_angle, or by area.
KOKKOS_INLINE_FUNCTION Real quad_light_pdf(const QuadLight& ql, const Vec3& p, const Vec3& wi,
                                           Real d2) {
  SphericalRect r;
  if (spherical_rect(ql, p, r)) return Real(1) / r.solid_angle;
  return d2 / (math::fabs(dot(ql.normal, wi)) * ql.area);
}

// Solid-angle pdf with which a shading point samples mesh light `ml` (area sampling) towards
// a point of normal nl at squared distance d2 in direction wi.
KOKKOS_INLINE_FUNCTION Real mesh_light_pdf(const MeshLight& ml, const Vec3& nl, const Vec3& wi,
                                           Real d2) {
  return d2 / (math::fabs(dot(nl, wi)) * ml.area);
}

// Power heuristic (Veach 1997, beta = 2) for the strategy of pdf `a` against one of pdf `b`,
// each scaled by its sample count; written as 1 / (1 + (b/a)^2) so that an infinite or zero
// pdf gives 0 or 1 instead of NaN.
KOKKOS_INLINE_FUNCTION Real power_heuristic(Real a, Real b) {
  const Real r = b / a;
  return Real(1) / (Real(1) + r * r);
}

// How a Lambertian shading point responds to light from wi: cos_s (the caller multiplies by
// Kd / pi); zero below the shading or the geometric normal. Shadow rays leave on ng's side.
struct LambertResponse {
  Vec3 ns, ng;
  KOKKOS_INLINE_FUNCTION Vec3 side() const { return ng; }
  KOKKOS_INLINE_FUNCTION Real operator()(const Vec3& wi, Real /*light_pdf*/) const {
    const Real cos_s = dot(ns, wi);
    if (cos_s <= Real(0) || dot(ng, wi) <= Real(0)) return Real(0);
    return cos_s;
  }
  KOKKOS_INLINE_FUNCTION Real delta(const Vec3& wi) const { return (*this)(wi, Real(0)); }
};

// How a glossy Phong lobe (around `axis`, exponent n) responds to light from wi: the lobe's
// pdf (the lobe's weight times it is the BSDF times cos) times the power-heuristic weight of
// light sampling (`light_count` samples) against sampling the lobe (`lobe_count` samples);
// zero on the wrong side of the surface (`side`: ng for reflection, -ng for transmission).
struct GlossyResponse {
  Vec3 axis, normal;
  Real shininess;
  Real light_count, lobe_count;
  KOKKOS_INLINE_FUNCTION Vec3 side() const { return normal; }
  KOKKOS_INLINE_FUNCTION Real lobe(const Vec3& wi) const {
    return dot(normal, wi) > Real(0) ? phong_pdf(axis, shininess, wi) : Real(0);
  }
  KOKKOS_INLINE_FUNCTION Real operator()(const Vec3& wi, Real light_pdf) const {
    const Real q = lobe(wi);
    return q > Real(0) ? q * power_heuristic(light_count * light_pdf, lobe_count * q) : Real(0);
  }
  KOKKOS_INLINE_FUNCTION Real delta(const Vec3& wi) const { return lobe(wi); }
};

// A run-time choice between the two responses above (`glossy`), so that a shading point's
// lobes can share one type in a LightLobes pass. Fields as in those: Lambert reads `axis` as
// ns and `side` as ng; the arithmetic is theirs.
struct LobeResponse {
  bool glossy = false;
  Vec3 axis, side_normal;
  Real shininess = 0, light_count = 1, lobe_count = 1;
  KOKKOS_INLINE_FUNCTION Vec3 side() const { return side_normal; }
  KOKKOS_INLINE_FUNCTION LambertResponse as_lambert() const { return {axis, side_normal}; }
  KOKKOS_INLINE_FUNCTION GlossyResponse as_glossy() const {
    return {axis, side_normal, shininess, light_count, lobe_count};
  }
  KOKKOS_INLINE_FUNCTION Real operator()(const Vec3& wi, Real light_pdf) const {
    return glossy ? as_glossy()(wi, light_pdf) : as_lambert()(wi, light_pdf);
  }
  KOKKOS_INLINE_FUNCTION Real delta(const Vec3& wi) const {
    return glossy ? as_glossy().delta(wi) : as_lambert().delta(wi);
  }
};

// One lobe's part in a light-sampling pass: whether it takes part, how it responds and the
// first random pair of its shadow samples (what ShadowPlan::pair_base is for a lone lobe).
template <class Response>
struct LightLobe {
  bool active = false;
  Response response;
  std::uint32_t pair_base = 0;
};

// A pass over the lights for one lobe alone (the host's way; trace_kernel.hpp).
template <class Response_>
struct OneLobe {
  using Response = Response_;
  static constexpr int kCount = 1;
  LightLobe<Response> lobe;
  KOKKOS_INLINE_FUNCTION const LightLobe<Response>& at(int) const { return lobe; }
};

// The lobes of one shading point that sample the lights in one pass (Lambert, a glossy
// lobe's reflection and transmission: the device's way), so that what depends on the point
// and a light alone (the spherical rectangle) is computed once for all of them. Lobes are
// picked by value, not by index into an array: a per-thread array indexed at run time would
// live in local memory.
struct LightLobes {
  using Response = LobeResponse;
  static constexpr int kCount = 3;
  LightLobe<LobeResponse> lambert, reflection, transmission;
  KOKKOS_INLINE_FUNCTION LightLobe<LobeResponse> at(int k) const {
    return k == 0 ? lambert : (k == 1 ? reflection : transmission);
  }
};

// What each lobe of a pass gathered, in the order of the pass's lobes (zero for lobes that
// took no part). Picked by value, like LightLobes.
struct LobeLight {
  Vec3 lambert{Real(0)}, reflection{Real(0)}, transmission{Real(0)};
  KOKKOS_INLINE_FUNCTION Vec3 at(int k) const {
    return k == 0 ? lambert : (k == 1 ? reflection : transmission);
  }
  KOKKOS_INLINE_FUNCTION void set(int k, const Vec3& v) {
    if (k == 0)
      lambert = v;
    else if (k == 1)
      reflection = v;
    else
      transmission = v;
  }
};

// For every active lobe of `lobes` (OneLobe or LightLobes), the sum over lights of
// L_e R(wi) / pdf(wi) (area lights, two-sided; pdf by solid angle, quads by spherical
// rectangle or area, mesh lights by area) and I R(wi) / r^2 (point lights), R the lobe's
// response (LambertResponse, or a glossy lobe times its MIS weight). Each lobe's sum runs
// over the same lights and samples, in the same order, as a pass of that lobe alone, so
// either way of passing gives the same sums.
// `kPaths` (FeatureBits) compiles in the glossy lobes (without kGlossy only the first lobe
// takes part), shaft culling, mesh lights and point lights; the caller leaves out only those
// its scene never uses.
template <unsigned kPaths = kEveryLightPath, class Scene, class Lobes>
KOKKOS_INLINE_FUNCTION LobeLight direct_light(const Scene& scene, const Surface& s, const Rng& rng,
                                              const ShadowPlan& plan, const Lobes& lobes,
                                              TraceCounter& c) {
  using Response = typename Lobes::Response;
  constexpr int kLobes = (kPaths & kGlossy) ? Lobes::kCount : 1;
  LobeLight out;
  const int samples = plan.soft ? plan.samples : 1;
  const Real inv_samples = Real(1) / Real(samples);
  auto area_sample = [&](Vec3& sum, const Response& response, const Vec3& org,
                         const bvh::ShaftBlockers* blockers, const Vec3& q, const Vec3& nl,
                         const Vec3& le, Real area) {
    const Vec3 w = q - s.p;
    const Real d2 = dot(w, w);
    if (!(d2 > Real(0))) return;
    const Vec3 wi = w / math::sqrt(d2);
    const Real cos_l = math::fabs(dot(nl, wi));
    const Real f = response(wi, d2 / (cos_l * area));
    if (!(f > Real(0)) || cos_l <= Real(0)) return;
    if (!visible(scene, org, q, s.time, c, blockers)) return;
    sum += le * (f * cos_l * area / d2 * inv_samples);
  };
  auto solid_angle_sample = [&](Vec3& sum, const Response& response, const Vec3& org,
                                const bvh::ShaftBlockers* blockers, const Vec3& q, const Vec3& le,
                                Real solid_angle) {
    const Vec3 w = q - s.p;
    const Real d2 = dot(w, w);
    if (!(d2 > Real(0))) return;
    const Vec3 wi = w / math::sqrt(d2);
    const Real f = response(wi, Real(1) / solid_angle);
    if (!(f > Real(0))) return;
    if (!visible(scene, org, q, s.time, c, blockers)) return;
    sum += le * (f * solid_angle * inv_samples);
  };
  const StrataShape shape = strata_shape(samples * plan.pixel_strata);
  int light = 0;
  for (int l = 0; l < scene.num_quads; ++l, ++light) {
    const QuadLight ql = scene.quads(l);
    SphericalRect rect;
    const bool by_solid_angle = plan.soft && spherical_rect(ql, s.p, rect);
    for (int k = 0; k < kLobes; ++k) {
      const LightLobe<Response> lobe = lobes.at(k);
      if (!lobe.active) continue;
      const Vec3 org = offset_ray_origin(s.p, lobe.response.side(), s.coordinate_bound);
      Vec3 sum = out.at(k);
      if (!plan.soft) {
        area_sample(sum, lobe.response, org, nullptr,
                    ql.corner + ql.u * Real(0.5) + ql.v * Real(0.5), ql.normal, ql.emission,
                    ql.area);
        out.set(k, sum);
        continue;
      }
      bvh::ShaftBlockers shaft;
      const bvh::ShaftBlockers* blockers = (kPaths & kShafts) && samples >= kShaftMinSamples &&
                                                   quad_shaft_blockers(scene, org, ql, shaft, c)
                                               ? &shaft
                                               : nullptr;
      const std::uint32_t key = plan.key ^ static_cast<std::uint32_t>(light);
      const std::uint32_t pair0 = lobe.pair_base + static_cast<std::uint32_t>(light * samples);
      // Consecutive pairs share one Philox block (Rng::uniform2 draws the same numbers).
      r123::Philox4x32::ctr_type block{};
      std::uint32_t block_id = ~0u;
      int cell = first_cell(plan);
      for (int j = 0; j < samples; ++j, cell = next_cell(plan, cell)) {
        const std::uint32_t pair = pair0 + static_cast<std::uint32_t>(j);
        if ((pair >> 1) != block_id) {
          block_id = pair >> 1;
          block = rng.block(block_id);
        }
        const unsigned o = (pair & 1u) * 2u;
        Real x, y;
        light_stratum(plan, j, cell, shape, key, Real(Rng::to_unit(block.v[o])),
                      Real(Rng::to_unit(block.v[o + 1])), x, y);
        if (by_solid_angle)
          solid_angle_sample(sum, lobe.response, org, blockers, spherical_rect_point(rect, x, y),
                             ql.emission, rect.solid_angle);
        else
          area_sample(sum, lobe.response, org, blockers, ql.corner + ql.u * x + ql.v * y, ql.normal,
                      ql.emission, ql.area);
      }
      out.set(k, sum);
    }
  }
  const int mesh_lights = (kPaths & kMeshLights) ? scene.num_mesh_lights : 0;
  for (int l = 0; l < mesh_lights; ++l, ++light) {
    const MeshLight ml = scene.mesh_lights(l);
    for (int k = 0; k < kLobes; ++k) {
      const LightLobe<Response> lobe = lobes.at(k);
      if (!lobe.active) continue;
      const Vec3 org = offset_ray_origin(s.p, lobe.response.side(), s.coordinate_bound);
      Vec3 sum = out.at(k);
      int cell = first_cell(plan);
      for (int j = 0; j < samples; ++j, cell = next_cell(plan, cell)) {
        float a, b;
        rng.uniform2(lobe.pair_base + static_cast<std::uint32_t>(light * samples + j), a, b);
        Real x = a, y = b;
        if (plan.soft)
          light_stratum(plan, j, cell, shape, plan.key ^ static_cast<std::uint32_t>(light), Real(a),
                        Real(b), x, y);
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
        area_sample(sum, lobe.response, org, nullptr, q, triangle_normal(t.a, t.b, t.c), le,
                    ml.area);
      }
      out.set(k, sum);
    }
  }
  const int point_lights = (kPaths & kPointLights) ? scene.num_points : 0;
  for (int l = 0; l < point_lights; ++l) {
    const PointLight pl = scene.points(l);
    const Vec3 w = pl.position - s.p;
    const Real d2 = dot(w, w);
    if (!(d2 > Real(0))) continue;
    const Vec3 wi = w / math::sqrt(d2);
    for (int k = 0; k < kLobes; ++k) {
      const LightLobe<Response> lobe = lobes.at(k);
      if (!lobe.active) continue;
      const Real f = lobe.response.delta(wi);
      if (!(f > Real(0))) continue;
      const Vec3 org = offset_ray_origin(s.p, lobe.response.side(), s.coordinate_bound);
      if (!visible(scene, org, pl.position, s.time, c)) continue;
      out.set(k, out.at(k) + pl.intensity * (f / d2));
    }
  }
  return out;
}

// direct_light for one lobe alone, the pass's only (first) lobe: its shadow samples' pairs from
// plan.pair_base.
template <unsigned kPaths = kEveryLightPath, class Scene, class Response>
KOKKOS_INLINE_FUNCTION Vec3 direct_light_one(const Scene& scene, const Surface& s, const Rng& rng,
                                             const ShadowPlan& plan, const Response& response,
                                             TraceCounter& c) {
  OneLobe<Response> lobe;
  lobe.lobe.active = true;
  lobe.lobe.response = response;
  lobe.lobe.pair_base = plan.pair_base;
  return direct_light<kPaths>(scene, s, rng, plan, lobe, c).at(0);
}

// Irradiance-like sum over lights of L_e cos_s / pdf (area lights) and I cos_s / r^2 (point
// lights); the caller multiplies by Kd / pi.
template <unsigned kPaths = kEveryLightPath, class Scene>
KOKKOS_INLINE_FUNCTION Vec3 direct_irradiance(const Scene& scene, const Surface& s, const Rng& rng,
                                              const ShadowPlan& plan, TraceCounter& c) {
  return direct_light_one<kPaths>(scene, s, rng, plan, LambertResponse{s.ns, s.ng}, c);
}

}  // namespace rtmini::sketch
