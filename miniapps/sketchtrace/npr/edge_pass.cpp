#include "passes.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/report/hash.hpp"

namespace rtmini::npr {
namespace detail {
namespace {

struct LineParams {
  float threshold = 0.f, full = 1.f;
  float grow = 0.f;  // dilation radius, pixels
  int reach = 0;     // window half-width, pixels
  float jitter = 0.f;
  std::uint64_t seed = 0;
};

// Stencil fraction -> line ink: 0 below the threshold, 1 from edge_full on.
KOKKOS_INLINE_FUNCTION float stencil_ink(const LineParams& p, float e) {
  if (!(e >= p.threshold) || e <= 0.f) return 0.f;
  return math::clamp((e - p.threshold) / compat::kmax(1e-6f, p.full - p.threshold), 0.f, 1.f);
}

// Smooth value noise in [-1, 1] on a lattice of 16 pixels (line wobble).
KOKKOS_INLINE_FUNCTION float wobble(std::uint64_t seed, float x, float y) {
  const float cell = 16.f;
  const float fx = math::floor(x / cell), fy = math::floor(y / cell);
  const float tx = x / cell - fx, ty = y / cell - fy;
  auto corner = [&](int i, int j) {
    const std::uint64_t key =
        (std::uint64_t(std::uint32_t(int(fx) + i)) << 32) | std::uint32_t(int(fy) + j);
    return float(hash_term(seed, key) >> 40) / float(1u << 24) * 2.f - 1.f;
  };
  const float sx = tx * tx * (3.f - 2.f * tx), sy = ty * ty * (3.f - 2.f * ty);
  return (1.f - sy) * ((1.f - sx) * corner(0, 0) + sx * corner(1, 0)) +
         sy * ((1.f - sx) * corner(0, 1) + sx * corner(1, 1));
}

// Line ink per pixel: the stencil ink grown by an anti-aliased disc of radius
// `grow` (a grey-scale dilation), sampled at a wobbled position when jittered.
DeviceImage line_ink_device(const DeviceImage& edge, const NprConfig& config) {
  LineParams p;
  p.threshold = config.edge_threshold;
  p.full = config.edge_full;
  p.grow = 0.5f * config.line_width;
  p.jitter = config.line_jitter;
  p.reach = static_cast<int>(math::ceil(p.grow + p.jitter)) + 1;
  p.seed = mix64(config.seed ^ 0x6c696e6573ULL);
  const int h = static_cast<int>(edge.extent(0)), w = static_cast<int>(edge.extent(1));
  DeviceImage ink("rtmini::sketchtrace::npr::line_ink", h, w, 1);
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::lines",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, h * w), KOKKOS_LAMBDA(int i) {
        const int x = i % w, y = i / w;
        float cx = float(x), cy = float(y);
        if (p.jitter > 0.f) {
          cx += p.jitter * wobble(p.seed, cx, cy);
          cy += p.jitter * wobble(p.seed ^ 0x9e3779b97f4a7c15ULL, cx, cy);
        }
        float best = 0.f;
        const int bx = static_cast<int>(math::floor(cx + 0.5f));
        const int by = static_cast<int>(math::floor(cy + 0.5f));
        for (int qy = by - p.reach; qy <= by + p.reach; ++qy)
          for (int qx = bx - p.reach; qx <= bx + p.reach; ++qx) {
            if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
            const float dx = float(qx) - cx, dy = float(qy) - cy;
            // Weight 1 within the grown radius, falling to 0 one pixel further out.
            const float wgt = math::clamp(p.grow + 1.f - math::sqrt(dx * dx + dy * dy), 0.f, 1.f);
            if (wgt > 0.f) best = compat::kmax(best, wgt * stencil_ink(p, edge(qy, qx, 0)));
          }
        ink(y, x, 0) = best;
      });
  return ink;
}

}  // namespace

void run_edges(const DeviceImage& rgb, const DeviceImage& edge, const NprConfig& config) {
  const DeviceImage ink = line_ink_device(edge, config);
  const float darkness = config.edge_darkness;
  const int w = static_cast<int>(rgb.extent(1));
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::edges",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, static_cast<int>(rgb.extent(0)) * w),
      KOKKOS_LAMBDA(int i) {
        const int x = i % w, y = i / w;
        const float f = 1.f - darkness * ink(y, x, 0);
        for (int c = 0; c < 3; ++c) rgb(y, x, c) *= f;
      });
}

}  // namespace detail

Image line_ink(const Image& edge, const NprConfig& config) {
  validate(config);
  return download_image(
      detail::line_ink_device(upload_image(edge, 1, "rtmini::sketchtrace::npr::edge"), config));
}

Image edge_pass(const Image& color, const Image& edge, const NprConfig& config) {
  validate(config);
  NprInputs in;
  in.color = &color;
  in.edge = &edge;
  validate(in);
  const DeviceImage rgb = upload_image(color, 3, "rtmini::sketchtrace::npr::rgb");
  detail::run_edges(rgb, upload_image(edge, 1, "rtmini::sketchtrace::npr::edge"), config);
  return download_image(rgb);
}

}  // namespace rtmini::npr
