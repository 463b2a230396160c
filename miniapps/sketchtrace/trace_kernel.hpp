#pragma once
// The per-pixel radiance kernel: stratified jittered pixel samples through a thin
// lens and a moving camera, then an iterative path (no recursion) of at most
// `bounces` secondary rays carrying a throughput weight. Local shading is Lambert
// diffuse lit by shadow-ray light sampling plus ambient; emission is counted where
// seen directly or after a specular/glossy continuation (after a diffuse one the
// light sampling already counted it). The first hit may fan out into
// `glossy_samples` glossy branches. Randomness: Rng(seed, pixel, sample) with a
// fixed dimension layout (README), so an image never depends on rank/thread/chunk.
#include "light_sampling.hpp"
#include "motion_trace.hpp"
#include "pixel_result.hpp"
#include "rtmini/scene/camera.hpp"
#include "surface_detail.hpp"

namespace rtmini::sketch {

// Scene features a kernel instantiation may skip (checked at launch time).
// kTextures: some material has image maps (surface_detail.hpp), looked up at ray-cone LODs.
// kMotion: the scene has moving objects (motion_trace.hpp); every path then sees one instant,
// the camera sample's time.
enum FeatureBits : unsigned {
  kSecondary = 1u,
  kLights = 2u,
  kCameraSampling = 4u,
  kTextures = 8u,
  kMotion = 16u
};

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
// time; continuation pairs from kContinuationPair; shadow pairs from kShadowPair.
inline constexpr std::uint32_t kContinuationPair = 4;
inline constexpr std::uint32_t kShadowPair = 1u << 24;

KOKKOS_INLINE_FUNCTION std::uint32_t pixel_key(std::uint64_t seed, std::uint64_t pixel,
                                               std::uint32_t tag) {
  return hash_u32(static_cast<std::uint32_t>(seed) ^
                  hash_u32(static_cast<std::uint32_t>(pixel) ^ hash_u32(tag + 0x632be5abu)));
}

template <unsigned kFeatures>
struct RadianceEstimator {
  KernelScene<kFeatures> scene;
  DeviceCamera camera;
  TraceParams p;

  // Lambert + ambient + emission at one surface; `emission` false after a diffuse bounce.
  KOKKOS_INLINE_FUNCTION Vec3 shade_local(const Surface& s, const DeviceMaterial& m, const Rng& rng,
                                          const ShadowPlan& plan, bool emission,
                                          TraceCounter& c) const {
    Vec3 l = emission ? m.emissive : Vec3(Real(0));
    const Vec3 kd = m.diffuse * m.opacity;
    if (max_component(kd) <= Real(0)) return l;
    Vec3 e = p.ambient;
    if (kFeatures & kLights) {
      Vec3 direct = direct_irradiance(scene, s, rng, plan, c) * Real(1.0 / math::kPi);
      if (kFeatures & kTextures) direct *= s.self_shadow;
      e += direct;
    }
    return l + kd * e;
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
    // S > 1: each pixel sample stratifies every light on its own. S = 1: the pixel
    // samples share the light's strata through a per-pixel random permutation (Cook
    // et al. 1984); an unpermuted split would correlate light strata with sub-pixel
    // position and bias the estimate.
    ShadowPlan first_plan;
    first_plan.samples = p.shadow_samples;
    first_plan.first = p.shadow_samples > 1 ? 0 : permute(i, p.spp, pixel_key(p.seed, pixel, 6));
    first_plan.strata = p.shadow_samples > 1 ? p.shadow_samples : p.spp;
    first_plan.pair_base = kShadowPair;
    first_plan.key = pixel_key(p.seed, pixel, 4);
    first_plan.soft = p.soft_shadows;
    Vec3 radiance = shade_local(s, m, rng, first_plan, true, c);
    if (!(kFeatures & kSecondary) || p.bounces == 0) return radiance;

    const int branches = is_glossy(m.shininess) ? p.glossy_samples : 1;
    const Real branch_weight = Real(1) / Real(branches);
    const int lights = scene.num_quads + scene.num_mesh_lights;
    for (int b = 0; b < branches; ++b) {
      float u_pick, unused, u1, u2;
      const std::uint32_t cp = kContinuationPair + 2u * static_cast<std::uint32_t>(b);
      rng.uniform2(cp, u_pick, unused);
      rng.uniform2(cp + 1, u1, u2);
      Ray next;
      next.time = ray.time;  // the whole path sees the camera sample's instant
      Vec3 weight;
      bool diffuse = false;
      if (!sample_continuation(m, s, ray.dir, p.indirect, u_pick, u1, u2, next, weight, diffuse))
        continue;
      Vec3 throughput = weight * branch_weight;
      RayCone branch_cone = cone;
      if (kFeatures & kTextures) branch_cone.scatter(m.shininess, is_glossy(m.shininess), diffuse);
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
        ShadowPlan plan;
        plan.samples = 1;
        plan.first = 0;
        plan.strata = 1;
        plan.pair_base =
            kShadowPair + slot * static_cast<std::uint32_t>(
                                     lights * (p.shadow_samples > 1 ? p.shadow_samples : 1));
        plan.soft = p.soft_shadows;
        radiance += throughput * shade_local(sd, md, rng, plan, !diffuse, c);
        if (depth == p.bounces) break;
        const std::uint32_t cq = kContinuationPair +
                                 2u * static_cast<std::uint32_t>(p.glossy_samples) +
                                 2u * (slot - 1u);
        rng.uniform2(cq, u_pick, unused);
        rng.uniform2(cq + 1, u1, u2);
        const Vec3 dir = next.dir;
        if (!sample_continuation(md, sd, dir, p.indirect, u_pick, u1, u2, next, weight, diffuse))
          break;
        throughput *= weight;
        if (kFeatures & kTextures)
          branch_cone.scatter(md.shininess, is_glossy(md.shininess), diffuse);
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
