#pragma once
// Renders any list of pixel chunks it is handed (the interface schedulers plug
// into): the chunks' pixels are flattened into one index list and traced by one
// kernel launch, specialised on the scene's features.
#include <vector>

#include "device_scene.hpp"
#include "stencil.hpp"
#include "trace_kernel.hpp"

namespace rtmini::sketch {

// A rectangle of pixels [x0, x0 + w) x [y0, y0 + h).
struct PixelChunk {
  int x0 = 0, y0 = 0, w = 0, h = 0;
  std::size_t pixels() const { return static_cast<std::size_t>(w) * static_cast<std::size_t>(h); }
};

class Renderer {
 public:
  Renderer(const HostScene& scene, const RenderSettings& settings);

  // Renders exactly the chunks' pixels; out[k] is the k-th pixel in chunk order,
  // each chunk row-major. Results depend only on scene, settings, seed and pixel.
  void render(const std::vector<PixelChunk>& chunks, std::vector<PixelResult>& out) const;
  // Renders the listed pixels (indices y * width + x); out[k] belongs to pixels[k].
  void render_pixels(const std::vector<std::int64_t>& pixels, std::vector<PixelResult>& out) const;
  // Cost probe for load balancing: one camera sample per listed pixel, no AOV or
  // stencil; out[k] estimates pixel k's cost per sample (traversal steps + rays).
  void probe(const std::vector<std::int64_t>& pixels, std::vector<float>& out) const;

  unsigned features() const { return features_; }
  const DeviceScene& scene() const { return scene_; }
  const DeviceCamera& camera() const { return camera_; }
  const TraceParams& params() const { return params_; }

 private:
  template <unsigned kFeatures>
  void launch(const TraceParams& params, bool aov,
              const Kokkos::View<std::int64_t*, MemSpace>& pixels,
              const Kokkos::View<PixelResult*, MemSpace>& out) const;
  // Launches the instantiation features_ names: the first of kKernelVariants[I..] equal to it.
  template <std::size_t I>
  void dispatch(const TraceParams& params, bool aov,
                const Kokkos::View<std::int64_t*, MemSpace>& pixels,
                const Kokkos::View<PixelResult*, MemSpace>& out) const;
  // Uploads `pixels`, runs the kernel specialised on features_ and copies the results back.
  void run(const TraceParams& params, bool aov, const std::vector<std::int64_t>& pixels,
           std::vector<PixelResult>& out) const;

  DeviceScene scene_;
  DeviceCamera camera_;
  TraceParams params_;
  StencilParams stencil_;
  bool aov_ = false;
  unsigned features_ = 0;
};

// The kernel instantiation a render that needs `wanted` (FeatureBits) runs: the first compiled
// one of the same shape (kShapeFeatures) that holds all the light paths it needs.
unsigned kernel_variant(unsigned wanted);

// Feature names for the banner, e.g. "secondary+lights".
std::string feature_names(unsigned features);

}  // namespace rtmini::sketch
