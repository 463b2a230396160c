#pragma once
// The per-pixel radiance kernel: stratified jittered pixel samples through a thin
// lens and a moving camera, then an iterative path (no recursion) of at most
// `bounces` secondary rays carrying a throughput weight. Every vertex samples the lights
// (next-event estimation) for its Lambert part and, for a glossy Phong lobe, through that
// lobe; emission a continuation finds counts in full after a perfect mirror or refraction
// (no light sample can find it), not at all after a diffuse bounce (light sampling alone
// counts it), and after a glossy one with the power-heuristic weight against light
// sampling (Veach 1997; light_sampling.hpp). The first hit and the vertices seen through
// mirrors and clear glass from it take all `shadow_samples`, jointly stratified with the
// pixel samples; later vertices one. The first hit may fan out into `glossy_samples`
// glossy branches. Randomness: Rng(seed, pixel, sample) with a fixed dimension layout
// (README), so an image never depends on rank/thread/chunk.
#include "kernel_features.hpp"
#include "light_sampling.hpp"
#include "motion_trace.hpp"
#include "pixel_result.hpp"
#include "rtmini/scene/camera.hpp"
#include "surface_detail.hpp"

namespace rtmini::sketch {

// The scene type a kernel holds: only kMotion kernels trace moving objects.
template <unsigned kFeatures>
using KernelScene = std::conditional_t<(kFeatures & kMotion) != 0, MovingScene, DeviceScene>;

struct TraceParams {
  int width = 1, height = 1;
  int spp = 1;
  int shadow_samples = 1;
  int bounces = 0;
  int glossy_samples = 1;
  bool soft_shadows = true;
  bool indirect = false;
  bool smooth = true;
  bool stats = false;
  bool probe = false;  // cost probe: PixelResult::tests = traversal work (nodes + tests)
  bool lens = false, motion = false;
  Vec3 background, ambient;
  std::uint64_t seed = 1;
  Real cone_spread = 0;  // one pixel's angle: the camera's ray-cone spread (textures.hpp)
};

// Random-number layout per (pixel, sample): pairs 0-1 pixel jitter and lens, pair 2
// time; continuation pairs from kContinuationPair; per path vertex (slot) a set of lights x
// shadow_samples pairs for Lambert shading from kShadowPair, two for the glossy lobes
// (reflection, transmission) from kGlossyShadowPair.
inline constexpr std::uint32_t kContinuationPair = 4;
inline constexpr std::uint32_t kShadowPair = 1u << 24;
inline constexpr std::uint32_t kGlossyShadowPair = 1u << 30;

KOKKOS_INLINE_FUNCTION std::uint32_t pixel_key(std::uint64_t seed, std::uint64_t pixel,
                                               std::uint32_t tag) {
  return hash_u32(static_cast<std::uint32_t>(seed) ^
                  hash_u32(static_cast<std::uint32_t>(pixel) ^ hash_u32(tag + 0x632be5abu)));
}

// kOnePassLobes: how a vertex's lobes sample the lights (gather_light); renderer.cpp picks it
// per backend.
template <unsigned kFeatures, bool kOnePassLobes = false>
struct RadianceEstimator {
  KernelScene<kFeatures> scene;
  DeviceCamera camera;
  TraceParams p;

  // Shadow-ray plan of path vertex `slot` (first hit 0) of pixel sample i: `full` (the first
  // hit and what mirrors and clear glass show of it) takes every shadow sample, jointly
  // stratified with the other pixel samples through a per-pixel permutation (Cook et al.
  // 1984; an unpermuted split would correlate light strata with sub-pixel position and bias
  // the estimate); other vertices take one.
  KOKKOS_INLINE_FUNCTION ShadowPlan vertex_plan(std::uint64_t pixel, int i, std::uint32_t slot,
                                                bool full) const {
    const int lights = scene.num_quads + scene.num_mesh_lights;
    ShadowPlan plan;
    plan.samples = full ? p.shadow_samples : 1;
    plan.pixel_strata = full ? p.spp : 1;
    plan.pixel_cell = full ? permute(i, p.spp, pixel_key(p.seed, pixel, 6)) : 0;
    plan.pair_base = kShadowPair + slot * shadow_set_pairs(lights);
    plan.key = pixel_key(p.seed, pixel, 4);
    plan.soft = p.soft_shadows;
    return plan;
  }

  KOKKOS_INLINE_FUNCTION std::uint32_t shadow_set_pairs(int lights) const {
    return static_cast<std::uint32_t>(lights * (p.shadow_samples > 1 ? p.shadow_samples : 1));
  }

  // Whether glossy lobes sampling the lights are compiled in.
  static constexpr bool kGlossyLight =
      (kFeatures & kLights) && (kFeatures & kSecondary) && (kFeatures & kGlossy);

  // Whether material m's glossy lobes sample the lights (then `spec` holds them).
  KOKKOS_INLINE_FUNCTION bool glossy_light(const Surface& s, const DeviceMaterial& m,
                                           const Vec3& dir, SpecularLobes& spec) const {
    if (!kGlossyLight || !is_glossy(m.shininess) || !p.soft_shadows || p.bounces == 0) return false;
    spec = specular_lobes(m, s, dir);
    return true;
  }

  // The lobes of a vertex that sample the lights: Lambert (`lambert`) and, with `glossy`, the
  // reflection and transmission of `spec` weighted against the lobe's own sampling
  // (`lobe_samples` continuation rays), each with its own set of random pairs.
  KOKKOS_INLINE_FUNCTION LightLobes light_lobes(const Surface& s, const DeviceMaterial& m,
                                                const ShadowPlan& plan, std::uint32_t slot,
                                                int lobe_samples, bool lambert, bool glossy,
                                                const SpecularLobes& spec) const {
    LightLobes lobes;
    lobes.lambert.active = lambert;
    lobes.lambert.response.axis = s.ns;
    lobes.lambert.response.side_normal = s.ng;
    lobes.lambert.pair_base = plan.pair_base;
    if (!glossy) return lobes;
    const std::uint32_t set = shadow_set_pairs(scene.num_quads + scene.num_mesh_lights);
    LobeResponse r;
    r.glossy = true;
    r.shininess = m.shininess;
    r.light_count = Real(plan.samples);
    r.lobe_count = Real(lobe_samples);
    lobes.reflection.active = max_component(spec.w_r) > Real(0);
    lobes.reflection.response = r;
    lobes.reflection.response.axis = spec.reflected;
    lobes.reflection.response.side_normal = s.ng;
    lobes.reflection.pair_base = kGlossyShadowPair + 2u * slot * set;
    lobes.transmission.active = max_component(spec.w_t) > Real(0);
    lobes.transmission.response = r;
    lobes.transmission.response.axis = spec.refracted;
    lobes.transmission.response.side_normal = -s.ng;
    lobes.transmission.pair_base = kGlossyShadowPair + (2u * slot + 1u) * set;
    return lobes;
  }

  // What the active lobes gather from the lights: all in one pass over the lights
  // (kOnePassLobes), or a pass per lobe with its own response type (LambertResponse,
  // GlossyResponse). The sums are the same (direct_light); renderer.cpp says which backend
  // takes which and why.
  KOKKOS_INLINE_FUNCTION LobeLight gather_light(const Surface& s, const Rng& rng,
                                                const ShadowPlan& plan, const LightLobes& lobes,
                                                TraceCounter& c) const {
    if constexpr (kOnePassLobes) {
      return direct_light<kFeatures>(scene, s, rng, plan, lobes, c);
    } else {
      LobeLight light;
      if (lobes.lambert.active)
        light.lambert = direct_light_one<kFeatures>(scene, s, rng, plan,
                                                    lobes.lambert.response.as_lambert(), c);
      ShadowPlan lobe_plan = plan;
      if (lobes.reflection.active) {
        lobe_plan.pair_base = lobes.reflection.pair_base;
        light.reflection = direct_light_one<kFeatures>(scene, s, rng, lobe_plan,
                                                       lobes.reflection.response.as_glossy(), c);
      }
      if (lobes.transmission.active) {
        lobe_plan.pair_base = lobes.transmission.pair_base;
        light.transmission = direct_light_one<kFeatures>(
            scene, s, rng, lobe_plan, lobes.transmission.response.as_glossy(), c);
      }
      return light;
    }
  }

  // Light a vertex sends back along -dir, less its emission: Lambert (ambient plus sampled
  // lights) and the glossy lobes' sampled lights.
  KOKKOS_INLINE_FUNCTION Vec3 shade_direct(const Surface& s, const DeviceMaterial& m,
                                           const Vec3& dir, const Rng& rng, const ShadowPlan& plan,
                                           std::uint32_t slot, int lobe_samples,
                                           TraceCounter& c) const {
    const Vec3 kd = m.diffuse * m.opacity;
    const bool lambert = max_component(kd) > Real(0);
    SpecularLobes spec;
    const bool glossy = glossy_light(s, m, dir, spec);
    LobeLight light;
    if ((kFeatures & kLights) && (lambert || glossy))
      light = gather_light(s, rng, plan,
                           light_lobes(s, m, plan, slot, lobe_samples, lambert, glossy, spec), c);
    Vec3 l(Real(0));
    if (lambert) {
      Vec3 e = p.ambient;
      if (kFeatures & kLights) {
        Vec3 direct = light.lambert * Real(1.0 / math::kPi);
        if (kFeatures & kTextures) direct *= s.self_shadow;  // parallax self-shadowing
        e += direct;
      }
      l = kd * e;
    }
    if (kGlossyLight) {
      Vec3 g(Real(0));
      if (glossy && max_component(spec.w_r) > Real(0)) g += spec.w_r * light.reflection;
      if (glossy && max_component(spec.w_t) > Real(0)) g += spec.w_t * light.transmission;
      l += g;
    }
    return l;
  }

  // Where a continuation ray left from and how it was drawn, for weighting emission it finds.
  struct Continuation {
    Vec3 from;
    Scatter kind = Scatter::kSpecular;
    Real lobe_pdf = 0, lobe_samples = 1, light_samples = 1;
  };

  // The weight of emission that continuation `k` finds at `sd` along unit direction wi:
  // 1 after a perfect mirror or refraction, 0 after a diffuse bounce (light sampling counted
  // it), after a glossy lobe the power heuristic of the lobe's pdf against the pdf with which
  // light sampling at k.from picks that point of that light.
  KOKKOS_INLINE_FUNCTION Real emission_weight(const Continuation& k, const Surface& sd,
                                              const Vec3& wi) const {
    if (k.kind == Scatter::kSpecular) return Real(1);
    if (k.kind == Scatter::kDiffuse) return Real(0);
    // Only a glossy continuation is left here (none without kGlossy).
    if (!(kFeatures & kLights) || !(kFeatures & kGlossy) || !p.soft_shadows) return Real(1);
    const int light = scene.light_of_object(sd.object);
    if (light < 0) return Real(1);
    const Vec3 w = sd.p - k.from;
    const Real d2 = dot(w, w);
    const Real light_pdf =
        light < scene.num_quads
            ? quad_light_pdf(scene.quads(light), k.from, wi, d2)
            : mesh_light_pdf(scene.mesh_lights(light - scene.num_quads), sd.ng, wi, d2);
    return power_heuristic(k.lobe_samples * k.lobe_pdf, k.light_samples * light_pdf);
  }

  KOKKOS_INLINE_FUNCTION Vec3 sample(std::uint64_t pixel, int x, int y, int i,
                                     TraceCounter& c) const {
    const Rng rng(p.seed, pixel, static_cast<std::uint32_t>(i));
    float jx, jy;
    rng.uniform2(0, jx, jy);
    Real sx, sy;
    stratum_2d(i, p.spp, pixel_key(p.seed, pixel, 0), Real(jx), Real(jy), sx, sy);
    Real lu = Real(0.5), lv = Real(0.5), tu = Real(0.5);
    if (kFeatures & kCameraSampling) {
      // Lens and time strata are permuted against the pixel strata (Cook et al. 1984).
      float a, b, t, unused;
      rng.uniform2(1, a, b);
      rng.uniform2(2, t, unused);
      const int lens_index = permute(i, p.spp, pixel_key(p.seed, pixel, 1));
      stratum_2d(lens_index, p.spp, pixel_key(p.seed, pixel, 2), Real(a), Real(b), lu, lv);
      tu =
          below_one((Real(permute(i, p.spp, pixel_key(p.seed, pixel, 3))) + Real(t)) / Real(p.spp));
    }
    Ray ray = camera.generate(Real(x) + sx, Real(y) + sy, lu, lv, tu, p.lens, p.motion);
    Hit hit = scene_closest(scene, ray, c);
    if (!hit.valid()) return p.background;
    Surface s = scene_surface(scene, ray, hit, p.smooth);
    DeviceMaterial m = scene.mesh.materials(s.material);
    RayCone cone{Real(0), p.cone_spread};
    if (kFeatures & kTextures) {
      cone.advance(hit.t);
      apply_surface_maps(scene, ray, hit, cone, s, m);
    }
    const int branches =
        (kFeatures & kSecondary) && p.bounces > 0 && is_glossy(m.shininess) ? p.glossy_samples : 1;
    const ShadowPlan first_plan = vertex_plan(pixel, i, 0, true);
    Vec3 radiance = m.emissive + shade_direct(s, m, ray.dir, rng, first_plan, 0, branches, c);
    if (!(kFeatures & kSecondary) || p.bounces == 0) return radiance;

    const Real branch_weight = Real(1) / Real(branches);
    for (int b = 0; b < branches; ++b) {
      float u_pick, unused, u1, u2;
      const std::uint32_t cp = kContinuationPair + 2u * static_cast<std::uint32_t>(b);
      rng.uniform2(cp, u_pick, unused);
      rng.uniform2(cp + 1, u1, u2);
      Ray next;
      next.time = ray.time;  // the whole path sees the camera sample's instant
      Vec3 weight;
      Continuation k;
      k.from = s.p;
      k.lobe_samples = Real(branches);
      k.light_samples = Real(first_plan.samples);
      if (!sample_continuation(m, s, ray.dir, p.indirect, u_pick, u1, u2, next, weight, k.kind,
                               k.lobe_pdf))
        continue;
      Vec3 throughput = weight * branch_weight;
      RayCone branch_cone = cone;
      if (kFeatures & kTextures)
        branch_cone.scatter(m.shininess, is_glossy(m.shininess), k.kind == Scatter::kDiffuse);
      bool through_specular = k.kind == Scatter::kSpecular;
      for (int depth = 1; depth <= p.bounces; ++depth) {
        const Hit h = scene_closest(scene, next, c);
        if (!h.valid()) {
          radiance += throughput * p.background;
          break;
        }
        Surface sd = scene_surface(scene, next, h, p.smooth);
        DeviceMaterial md = scene.mesh.materials(sd.material);
        if (kFeatures & kTextures) {
          branch_cone.advance(h.t);
          apply_surface_maps(scene, next, h, branch_cone, sd, md);
        }
        // Vertex slot for random numbers: first hit = 0, then per branch and depth.
        const std::uint32_t slot = 1u + static_cast<std::uint32_t>(b * p.bounces + depth - 1);
        const ShadowPlan plan = vertex_plan(pixel, i, slot, through_specular);
        const Real emission =
            max_component(md.emissive) > Real(0) ? emission_weight(k, sd, next.dir) : Real(0);
        radiance += throughput * (md.emissive * emission +
                                  shade_direct(sd, md, next.dir, rng, plan, slot, 1, c));
        if (depth == p.bounces) break;
        const std::uint32_t cq = kContinuationPair +
                                 2u * static_cast<std::uint32_t>(p.glossy_samples) +
                                 2u * (slot - 1u);
        rng.uniform2(cq, u_pick, unused);
        rng.uniform2(cq + 1, u1, u2);
        const Vec3 dir = next.dir;
        k.from = sd.p;
        k.lobe_samples = Real(1);
        k.light_samples = Real(plan.samples);
        if (!sample_continuation(md, sd, dir, p.indirect, u_pick, u1, u2, next, weight, k.kind,
                                 k.lobe_pdf))
          break;
        through_specular = through_specular && k.kind == Scatter::kSpecular;
        throughput *= weight;
        if (kFeatures & kTextures)
          branch_cone.scatter(md.shininess, is_glossy(md.shininess), k.kind == Scatter::kDiffuse);
      }
    }
    return radiance;
  }

  KOKKOS_INLINE_FUNCTION void pixel(int x, int y, PixelResult& out, TraceCounter& c) const {
    const std::uint64_t index =
        static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(p.width) + x;
    Vec3 sum(Real(0));
    for (int i = 0; i < p.spp; ++i) sum += sample(index, x, y, i, c);
    const Real inv = Real(1) / Real(p.spp);
    out.r = static_cast<float>(sum.x * inv);
    out.g = static_cast<float>(sum.y * inv);
    out.b = static_cast<float>(sum.z * inv);
  }
};

}  // namespace rtmini::sketch
