// sketchtrace-post --stats: how well a drawing reproduces its render's tone and
// silhouettes. Host code: it runs once per image and must not depend on the
// backend's reduction order.
#include <cmath>
#include <vector>

#include "npr.hpp"

namespace rtmini::npr {
namespace {

using Plane = std::vector<double>;

// Separable Gaussian blur with clamped borders (sigma in pixels).
Plane gaussian_blur(const Plane& in, int w, int h, double sigma) {
  const int r = static_cast<int>(std::ceil(3.0 * sigma));
  std::vector<double> kernel(2 * r + 1);
  double norm = 0;
  for (int i = -r; i <= r; ++i) norm += kernel[i + r] = std::exp(-0.5 * i * i / (sigma * sigma));
  for (double& k : kernel) k /= norm;
  Plane tmp(in.size()), out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i)
        s += kernel[i + r] * in[std::size_t(y) * w + std::min(w - 1, std::max(0, x + i))];
      tmp[std::size_t(y) * w + x] = s;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double s = 0;
      for (int i = -r; i <= r; ++i)
        s += kernel[i + r] * tmp[std::size_t(std::min(h - 1, std::max(0, y + i))) * w + x];
      out[std::size_t(y) * w + x] = s;
    }
  return out;
}

// Displayed (sRGB-encoded) luminance of a linear RGB pixel of the drawing.
double drawn_tone(const Image& img, int x, int y) {
  const int c = img.channels;
  const double r = srgb_encode(img.at(x, y, 0));
  const double g = c >= 3 ? srgb_encode(img.at(x, y, 1)) : r;
  const double b = c >= 3 ? srgb_encode(img.at(x, y, 2)) : r;
  return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

void measure_tone(const Image& color, const Image& drawing, const NprConfig& config,
                  QualityStats& q) {
  const int w = color.width, h = color.height;
  const float inv_white = 1.f / exposure_white(color, config);
  Plane render(std::size_t(w) * h), drawn(render.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float r = std::max(0.f, color.at(x, y, 0));
      const float g = color.channels >= 3 ? std::max(0.f, color.at(x, y, 1)) : r;
      const float b = color.channels >= 3 ? std::max(0.f, color.at(x, y, 2)) : r;
      render[std::size_t(y) * w + x] = render_tone(r, g, b, inv_white);
      drawn[std::size_t(y) * w + x] = drawn_tone(drawing, x, y);
    }
  const double sigma = 0.5 * config.cell_size;
  render = gaussian_blur(render, w, h, sigma);
  drawn = gaussian_blur(drawn, w, h, sigma);
  const double n = double(render.size());
  double mr = 0, md = 0, err = 0;
  for (std::size_t i = 0; i < render.size(); ++i) {
    mr += render[i];
    md += drawn[i];
    err += std::fabs(render[i] - drawn[i]);
  }
  mr /= n;
  md /= n;
  double srr = 0, sdd = 0, srd = 0;
  for (std::size_t i = 0; i < render.size(); ++i) {
    srr += (render[i] - mr) * (render[i] - mr);
    sdd += (drawn[i] - md) * (drawn[i] - md);
    srd += (render[i] - mr) * (drawn[i] - md);
  }
  q.has_tone = true;
  q.tone_correlation = srr > 0 && sdd > 0 ? srd / std::sqrt(srr * sdd) : 0.0;
  q.tone_mean_abs_error = err / n;
}

// Pixels on the near side of an object-id change to a 4-neighbour.
std::vector<char> geometric_silhouettes(const Image& object, const Image* depth) {
  const int w = object.width, h = object.height;
  std::vector<char> sil(std::size_t(w) * h, 0);
  const int dx[] = {1, -1, 0, 0}, dy[] = {0, 0, 1, -1};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float id = object.at(x, y, 0);
      if (id < 0) continue;  // the background draws no line
      for (int k = 0; k < 4; ++k) {
        const int nx = x + dx[k], ny = y + dy[k];
        if (nx < 0 || ny < 0 || nx >= w || ny >= h || object.at(nx, ny, 0) == id) continue;
        const bool behind = object.at(nx, ny, 0) < 0 || depth == nullptr ||
                            depth->at(nx, ny, 0) >= depth->at(x, y, 0);
        if (behind) sil[std::size_t(y) * w + x] = 1;
      }
    }
  return sil;
}

// Every set pixel within Chebyshev distance `r` of a set pixel of `mask`.
std::vector<char> dilate(const std::vector<char>& mask, int w, int h, int r) {
  std::vector<char> out(mask.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!mask[std::size_t(y) * w + x]) continue;
      for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
        for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i)
          out[std::size_t(j) * w + i] = 1;
    }
  return out;
}

void measure_lines(const NprInputs& in, const Image& drawing, const NprConfig& config,
                   QualityStats& q) {
  const int w = in.color->width, h = in.color->height;
  const std::vector<char> sil = geometric_silhouettes(*in.object, in.depth);
  const Image ink = line_ink(*in.edge, config);
  std::vector<char> line(sil.size(), 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) line[std::size_t(y) * w + x] = ink.at(x, y, 0) >= 0.5f;
  // A drawn line may lie anywhere within its own grown half-width of the silhouette.
  const int reach = 1 + static_cast<int>(std::ceil(0.5 * config.line_width));
  const std::vector<char> near_sil = dilate(sil, w, h, reach), near_line = dilate(line, w, h, 1);
  double n_sil = 0, found = 0, n_line = 0, on_sil = 0, dark = 0;
  for (std::size_t i = 0; i < sil.size(); ++i) {
    n_sil += sil[i];
    found += sil[i] && near_line[i];
    if (!line[i]) continue;
    n_line += 1;
    on_sil += near_sil[i];
    dark += 1.0 - drawn_tone(drawing, int(i % w), int(i / w));
  }
  q.has_lines = true;
  q.silhouette_pixels = n_sil;
  q.line_pixels = n_line;
  q.line_recall = n_sil > 0 ? found / n_sil : 1.0;
  q.line_precision = n_line > 0 ? on_sil / n_line : 0.0;
  q.line_darkness = n_line > 0 ? dark / n_line : 0.0;
}

}  // namespace

QualityStats measure_quality(const NprInputs& in, const Image& drawing, const NprConfig& config) {
  validate(config);
  validate(in);
  QualityStats q;
  measure_tone(*in.color, drawing, config, q);
  if (in.object != nullptr && in.edge != nullptr && config.pass_edges)
    measure_lines(in, drawing, config, q);
  return q;
}

}  // namespace rtmini::npr
