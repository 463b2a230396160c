#include "passes.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::npr {
namespace detail {

void run_edges(const DeviceImage& rgb, const DeviceImage& edge, const NprConfig& config) {
  const float darkness = config.edge_darkness, threshold = config.edge_threshold;
  const int w = static_cast<int>(rgb.extent(1));
  // Anti-aliased silhouettes (Choudhury & Parker, NPAR 2009): the darkening is
  // proportional to the fraction of stencil rays that hit another object.
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::edges",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, static_cast<int>(rgb.extent(0)) * w),
      KOKKOS_LAMBDA(int i) {
        const int x = i % w, y = i / w;
        const float e = math::clamp(edge(y, x, 0), 0.f, 1.f);
        if (!(e >= threshold) || e <= 0.f) return;
        const float f = 1.f - darkness * e;
        for (int c = 0; c < 3; ++c) rgb(y, x, c) *= f;
      });
}

}  // namespace detail

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
