#pragma once
// Images as device Views (height, width, channel) for the per-pixel NPR kernels,
// and the copies between them and host Images.
#include <string>

#include "rtmini/io/image.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini::npr {

using DeviceImage =
    Kokkos::View<float***, Kokkos::LayoutRight, Kokkos::DefaultExecutionSpace::memory_space>;

// Copy of `image` on the device with `channels` channels: grey is replicated to
// RGB, extra channels (alpha) are dropped, a missing channel is 0.
DeviceImage upload_image(const Image& image, int channels, const std::string& label);

Image download_image(const DeviceImage& image);

}  // namespace rtmini::npr
