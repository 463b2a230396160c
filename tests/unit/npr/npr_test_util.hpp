#pragma once
// Synthetic inputs shared by the NPR tests.
#include <cmath>

#include "rtmini/io/image.hpp"

namespace rtmini::npr::test {

// Horizontal ramp of linear grey from 0 (left) to 1 (right).
inline Image gradient_image(int w, int h) {
  Image img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) img.at(x, y, c) = float(x) / float(w - 1);
  return img;
}

// A reddish shaded disk on a light background, and its anti-aliased silhouette
// map: the fraction of 8 ring samples of radius 1.5 px whose inside/outside
// differs from the centre's, as the renderer's stencil would report.
inline void disk_scene(int w, int h, Image& color, Image& edge) {
  color = Image(w, h, 3);
  edge = Image(w, h, 1);
  const float cx = 0.5f * w, cy = 0.5f * h, r = 0.35f * std::fmin(w, h);
  auto inside = [&](float x, float y) { return (x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float px = x + 0.5f, py = y + 0.5f;
      if (inside(px, py)) {
        // Lambert shading from a light at the upper left.
        const float nx = (px - cx) / r, ny = (py - cy) / r;
        const float nz = std::sqrt(std::fmax(0.f, 1.f - nx * nx - ny * ny));
        const float s = std::fmax(0.f, -0.5f * nx - 0.5f * ny + 0.7071f * nz);
        color.at(x, y, 0) = 0.9f * s;
        color.at(x, y, 1) = 0.35f * s;
        color.at(x, y, 2) = 0.2f * s;
      } else {
        for (int c = 0; c < 3; ++c) color.at(x, y, c) = 0.8f - 0.5f * float(y) / float(h);
      }
      const bool centre = inside(px, py);
      int differ = 0;
      for (int k = 0; k < 8; ++k) {
        const float a = 0.7853982f * k;
        differ += inside(px + 1.5f * std::cos(a), py + 1.5f * std::sin(a)) != centre ? 1 : 0;
      }
      edge.at(x, y, 0) = float(differ) / 8.f;
    }
}

}  // namespace rtmini::npr::test
