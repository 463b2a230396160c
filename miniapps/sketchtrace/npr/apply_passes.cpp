#include "passes.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini::npr {

Image apply_passes(const NprInputs& inputs, const NprConfig& config) {
  validate(config);
  validate(inputs);
  Kokkos::Profiling::pushRegion("rtmini::sketchtrace::npr");
  const DeviceImage rgb = upload_image(*inputs.color, 3, "rtmini::sketchtrace::npr::rgb");
  if (config.pass_hatch) {
    const DeviceImage object =
        inputs.object ? upload_image(*inputs.object, 1, "rtmini::sketchtrace::npr::object")
                      : DeviceImage("rtmini::sketchtrace::npr::no_object", 0, 0, 1);
    detail::run_tone(rgb, object, config, exposure_white(*inputs.color, config));
  }
  if (config.pass_edges && inputs.edge != nullptr)
    detail::run_edges(rgb, upload_image(*inputs.edge, 1, "rtmini::sketchtrace::npr::edge"), config);
  // The paper is composited last so it shows through strokes and edges alike (seed §6).
  if (config.pass_paper) detail::run_paper(rgb, config);
  Image out = download_image(rgb);
  Kokkos::Profiling::popRegion();
  return out;
}

}  // namespace rtmini::npr
