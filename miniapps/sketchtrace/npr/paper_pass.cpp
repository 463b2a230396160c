#include "paper.hpp"
#include "passes.hpp"

namespace rtmini::npr {
namespace detail {

void run_paper(const DeviceImage& rgb, const NprConfig& config) {
  PaperParams params;
  PermutationView perm;
  make_paper(config, params, perm);
  const int w = static_cast<int>(rgb.extent(1));
  Kokkos::parallel_for(
      "rtmini::sketchtrace::npr::paper",
      Kokkos::RangePolicy<Kokkos::DefaultExecutionSpace>(0, static_cast<int>(rgb.extent(0)) * w),
      KOKKOS_LAMBDA(int i) {
        const int x = i % w, y = i / w;
        const float f = paper_factor(params, perm, x, y);
        for (int c = 0; c < 3; ++c) rgb(y, x, c) *= f;
      });
}

}  // namespace detail

Image paper_pass(const Image& color, const NprConfig& config) {
  validate(config);
  const DeviceImage rgb = upload_image(color, 3, "rtmini::sketchtrace::npr::rgb");
  detail::run_paper(rgb, config);
  return download_image(rgb);
}

}  // namespace rtmini::npr
