#include "device_image.hpp"

namespace rtmini::npr {

DeviceImage upload_image(const Image& image, int channels, const std::string& label) {
  const int w = image.width, h = image.height, c_in = image.channels;
  // Reshape on the host (cheap, done once per input) so the kernels see a fixed layout.
  Kokkos::View<float***, Kokkos::LayoutRight, Kokkos::HostSpace> host(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, label + "_host"), h, w, channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c) {
        float v = 0.f;
        if (c_in == 1)
          v = image.at(x, y, 0);
        else if (c < c_in)
          v = image.at(x, y, c);
        host(y, x, c) = v;
      }
  DeviceImage dev(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), h, w, channels);
  Kokkos::deep_copy(dev, host);
  return dev;
}

Image download_image(const DeviceImage& image) {
  Image out(static_cast<int>(image.extent(1)), static_cast<int>(image.extent(0)),
            static_cast<int>(image.extent(2)));
  Kokkos::View<float***, Kokkos::LayoutRight, Kokkos::HostSpace, Kokkos::MemoryUnmanaged> host(
      out.data.data(), image.extent(0), image.extent(1), image.extent(2));
  Kokkos::deep_copy(host, image);
  return out;
}

}  // namespace rtmini::npr
