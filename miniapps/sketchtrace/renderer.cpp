#include "renderer.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rtmini::sketch {
namespace {

// One pixel: the radiance samples, then (when AOVs or edges are wanted) the
// pinhole centre ray for depth/normal/object and the edge stencil.
template <unsigned kFeatures>
struct PixelKernel {
  // How a vertex's lobes (Lambert, glossy reflection, glossy transmission) sample the lights,
  // by backend: one pass over the lights for all of them where the execution space cannot reach
  // host memory (a GPU), a pass per lobe on the host. Both give the same sums in the same
  // order (RadianceEstimator::gather_light), so every host hash is the same either way; they
  // differ in what the compiler makes of them. Measured (results/gpu/README.md, "sketchtrace's
  // GPU slowdown"): on an H100 the one pass rendered dist_first 1000x800 32 spp in 0.383-0.396 s
  // against 0.526-0.559 s for the pass per lobe (-27 %; the 4K two-sphere, no glossy lobes,
  // unchanged), while on the host (OpenMP, 2 threads) it rendered dist_first 8-44 % slower in 5
  // of 5 alternated pairs. On CUDA the one pass moves dist_first's hash (18b8a1b1d0ddc23f ->
  // c599089d83fc4b1b): nvcc contracts multiply-adds across the restructured code differently
  // (the host build has -ffp-contract=off).
  static constexpr bool kOnePassLobes =
      !Kokkos::SpaceAccessibility<Kokkos::DefaultExecutionSpace, Kokkos::HostSpace>::accessible;
  RadianceEstimator<kFeatures, kOnePassLobes> est;
  StencilParams stencil;
  bool aov;
  Kokkos::View<const std::int64_t*, MemSpace> pixels;
  Kokkos::View<PixelResult*, MemSpace> out;

  KOKKOS_INLINE_FUNCTION void operator()(const std::int64_t k) const {
    const std::int64_t index = pixels(k);
    const int x = static_cast<int>(index % est.p.width), y = static_cast<int>(index / est.p.width);
    TraceCounter c;
    c.stats = est.p.stats;
    PixelResult r;
    est.pixel(x, y, r, c);
    if (aov) {
      const StencilHit centre =
          stencil_hit(est.scene, est.camera, Real(x) + Real(0.5), Real(y) + Real(0.5), stencil, c);
      r.object = centre.object;
      r.depth = static_cast<float>(centre.depth);
      r.nx = static_cast<float>(centre.normal.x);
      r.ny = static_cast<float>(centre.normal.y);
      r.nz = static_cast<float>(centre.normal.z);
      if (stencil.edges && stencil.radius > Real(0)) {
        Real sum = 0;
        for (int j = 0; j < stencil.samples; ++j) {
          const Rng rng(est.p.seed, static_cast<std::uint64_t>(index),
                        0x80000000u + static_cast<std::uint32_t>(j));
          float a, b;
          rng.uniform2(0, a, b);
          Real sx, sy;
          stratum_2d(j, stencil.samples,
                     pixel_key(est.p.seed, static_cast<std::uint64_t>(index), 5), Real(a), Real(b),
                     sx, sy);
          sum += stencil_fraction(est.scene, est.camera, Real(x) + sx, Real(y) + sy, stencil, c);
        }
        r.edge = static_cast<float>(sum / Real(stencil.samples));
      }
    }
    r.rays = c.rays;
    r.tests = est.p.probe ? c.tests + c.nodes : c.tests;
    out(k) = r;
  }
};

// The kernel instantiations compiled. Each shape (kShapeFeatures) a scene can have has a
// general one with every light path; lean ones leave out light paths the bundled scenes do not
// use (all have one quad light: no mesh or point lights), listed first so that they win.
constexpr unsigned kKernelVariants[] = {
    // Lean: quad lights only.
    kLights,                                           // direct light only (penumbra)
    kSecondary | kLights | kShafts,                    // mirrors, >= 8 shadow rays (two_spheres)
    kSecondary | kLights | kGlossy,                    // glossy, few shadow rays (spheres)
    kSecondary | kLights | kCameraSampling | kGlossy,  // ... through a lens (dist_first)
    // General: every light path of each shape.
    0u, kSecondary, kLights | kEveryLightPath, kSecondary | kLights | kEveryLightPath,
    kCameraSampling, kSecondary | kCameraSampling, kLights | kCameraSampling | kEveryLightPath,
    kSecondary | kLights | kCameraSampling | kEveryLightPath,
    kTextures | kSecondary | kLights | kEveryLightPath,
    kTextures | kSecondary | kLights | kCameraSampling | kEveryLightPath,
    kSecondary | kLights | kCameraSampling | kMotion | kEveryLightPath,
    kSecondary | kLights | kCameraSampling | kMotion | kTextures | kEveryLightPath};
constexpr std::size_t kNumKernelVariants = sizeof(kKernelVariants) / sizeof(kKernelVariants[0]);

// The light paths a scene's light sampling can take (FeatureBits; kernel_features.hpp).
unsigned light_paths(const DeviceScene& scene, const RenderSettings& s) {
  unsigned f = 0;
  // Glossy light sampling and MIS weights need soft shadows and a continuation to weigh.
  if (scene.any_glossy && s.soft_shadows && s.bounces > 0) f |= kGlossy;
  if (s.soft_shadows && s.shadow_samples >= kShaftMinSamples) f |= kShafts;
  if (scene.num_mesh_lights > 0) f |= kMeshLights;
  if (scene.num_points > 0) f |= kPointLights;
  return f;
}

}  // namespace

unsigned kernel_variant(unsigned wanted) {
  for (unsigned v : kKernelVariants)
    if ((v & kShapeFeatures) == (wanted & kShapeFeatures) && (v & wanted) == wanted) return v;
  throw std::logic_error("sketchtrace: no kernel instantiation for features " +
                         feature_names(wanted));
}

std::string feature_names(unsigned f) {
  std::string s;
  auto add = [&](unsigned bit, const char* name) {
    if (f & bit) s += (s.empty() ? "" : "+") + std::string(name);
  };
  add(kSecondary, "secondary");
  add(kLights, "lights");
  add(kCameraSampling, "camera-sampling");
  add(kTextures, "textures");
  add(kMotion, "motion");
  add(kGlossy, "glossy");
  add(kShafts, "shafts");
  add(kMeshLights, "mesh-lights");
  add(kPointLights, "point-lights");
  return s.empty() ? "primary-only" : s;
}

Renderer::Renderer(const HostScene& scene, const RenderSettings& s) {
  const double cos_crease = std::cos(s.crease_angle_deg * math::kPi / 180.0);
  scene_ = upload_scene(scene, s.bvh, cos_crease);
  camera_ = make_camera(to_render_frame(s.camera, scene.origin), s.width, s.height);
  params_.width = s.width;
  params_.height = s.height;
  params_.spp = s.spp;
  params_.shadow_samples = s.shadow_samples;
  params_.bounces = s.bounces;
  params_.glossy_samples = s.glossy_samples;
  params_.soft_shadows = s.soft_shadows;
  params_.indirect = s.indirect;
  params_.smooth = s.smooth;
  params_.stats = s.stats;
  params_.background = Vec3(s.background);
  params_.ambient = Vec3(s.ambient);
  params_.seed = s.seed;
  // One pixel's angle (RTG ch. 20): up is scaled to the image plane's half height.
  // A zero spread (--texture-filter none) makes every cone width 0: level 0 everywhere.
  params_.cone_spread =
      s.texture_filter == "none"
          ? Real(0)
          : static_cast<Real>(std::atan(2.0 * length(Vec3d(camera_.up)) /
                                        length(Vec3d(camera_.forward)) / s.height));
  params_.lens = s.camera.aperture > 0.0;
  params_.motion =
      s.camera.shutter_close > s.camera.shutter_open && length(s.camera.velocity) > 0.0;
  stencil_.radius = static_cast<Real>(s.edge_thickness);
  stencil_.cos_crease = static_cast<Real>(cos_crease);
  stencil_.depth_threshold = static_cast<Real>(s.depth_threshold);
  stencil_.samples = s.stencil_samples;
  stencil_.edges = s.needs_edges();
  stencil_.smooth = s.smooth;
  aov_ = s.needs_aov_pass();
  unsigned wanted = 0;
  if ((scene_.any_secondary || s.indirect) && s.bounces > 0) wanted |= kSecondary;
  if (scene_.num_quads + scene_.num_mesh_lights + scene_.num_points > 0) wanted |= kLights;
  if (params_.lens || params_.motion) wanted |= kCameraSampling;
  if (s.general_kernel) wanted = kSecondary | kLights | kCameraSampling | kEveryLightPath;
  // Textured scenes get two instantiations only, with secondary rays and lights compiled in
  // (both are checked at run time too), so the untextured kernels stay as they were.
  if (scene_.maps.any) wanted |= kTextures | kSecondary | kLights;
  // Moving objects: the general kernel with motion (one more instantiation, not eight; two
  // with textures); the time sample comes with camera sampling.
  if (scene_.motion.count > 0)
    wanted = kSecondary | kLights | kCameraSampling | kMotion | (wanted & kTextures);
  // Light paths only matter where light is sampled, glossy lobes' only with secondary rays.
  if (wanted & kLights) wanted |= light_paths(scene_, s);
  if (!(wanted & kSecondary)) wanted &= ~kGlossy;
  features_ = kernel_variant(wanted);
}

template <unsigned kFeatures>
void Renderer::launch(const TraceParams& params, bool aov,
                      const Kokkos::View<std::int64_t*, MemSpace>& pixels,
                      const Kokkos::View<PixelResult*, MemSpace>& out) const {
  PixelKernel<kFeatures> kernel{{scene_, camera_, params}, stencil_, aov, pixels, out};
  using Policy =
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace, Kokkos::Schedule<Kokkos::Dynamic>,
                          Kokkos::IndexType<std::int64_t>>;
  Kokkos::parallel_for("rtmini::sketch::render",
                       Policy(0, static_cast<std::int64_t>(pixels.extent(0))), kernel);
}

template <std::size_t I>
void Renderer::dispatch(const TraceParams& params, bool aov,
                        const Kokkos::View<std::int64_t*, MemSpace>& pixels,
                        const Kokkos::View<PixelResult*, MemSpace>& out) const {
  if constexpr (I < kNumKernelVariants) {
    if (features_ == kKernelVariants[I])
      launch<kKernelVariants[I]>(params, aov, pixels, out);
    else
      dispatch<I + 1>(params, aov, pixels, out);
  }
}

void Renderer::run(const TraceParams& params, bool aov, const std::vector<std::int64_t>& list,
                   std::vector<PixelResult>& out) const {
  const std::size_t n = list.size();
  out.resize(n);
  if (n == 0) return;
  Kokkos::View<std::int64_t*, MemSpace> pixels("rtmini::sketch::pixel_list", n);
  Kokkos::View<PixelResult*, MemSpace> results("rtmini::sketch::pixel_results", n);
  auto hp = Kokkos::create_mirror_view(pixels);
  for (std::size_t k = 0; k < n; ++k) hp(k) = list[k];
  Kokkos::deep_copy(pixels, hp);
  dispatch<0>(params, aov, pixels, results);
  auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), results);
  for (std::size_t i = 0; i < n; ++i) out[i] = hr(i);
}

void Renderer::render_pixels(const std::vector<std::int64_t>& pixels,
                             std::vector<PixelResult>& out) const {
  run(params_, aov_, pixels, out);
}

void Renderer::render(const std::vector<PixelChunk>& chunks, std::vector<PixelResult>& out) const {
  std::vector<std::int64_t> list;
  for (const PixelChunk& c : chunks)
    for (int y = c.y0; y < c.y0 + c.h; ++y)
      for (int x = c.x0; x < c.x0 + c.w; ++x)
        list.push_back(static_cast<std::int64_t>(y) * params_.width + x);
  run(params_, aov_, list, out);
}

void Renderer::probe(const std::vector<std::int64_t>& pixels, std::vector<float>& out) const {
  TraceParams p = params_;
  p.spp = 1;
  p.glossy_samples = 1;
  p.stats = true;
  p.probe = true;
  std::vector<PixelResult> r;
  run(p, false, pixels, r);
  out.resize(r.size());
  // Cost model: traversal work (nodes visited + triangles tested) plus 4 steps per
  // ray for generation and shading. Fitted on the two-sphere scene (400x300, 16 spp,
  // 256-pixel dispatches on 1 core): per-dispatch time error 12 % mean, against 78 %
  // for rays alone.
  for (std::size_t k = 0; k < r.size(); ++k)
    out[k] = static_cast<float>(static_cast<double>(r[k].tests) + 4.0 * r[k].rays);
}

}  // namespace rtmini::sketch
