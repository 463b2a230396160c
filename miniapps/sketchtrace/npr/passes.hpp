#pragma once
// The passes as in-place kernels on device images, so apply_passes uploads the
// inputs once and downloads the result once.
#include "device_image.hpp"
#include "npr.hpp"

namespace rtmini::npr::detail {

// rgb: (h, w, 3). Hatching or colour pencil according to config.style; object:
// (h, w, 1) object ids, or extent 0 when there is no object AOV; white: exposure_white.
void run_tone(const DeviceImage& rgb, const DeviceImage& object, const NprConfig& config,
              float white);
// edge: (h, w, 1), the stencil's fraction of differing hits in [0, 1].
void run_edges(const DeviceImage& rgb, const DeviceImage& edge, const NprConfig& config);
void run_paper(const DeviceImage& rgb, const NprConfig& config);

}  // namespace rtmini::npr::detail
