#include "map_errors.hpp"

#include <algorithm>
#include <cmath>

#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/sampling/fibonacci.hpp"

namespace rtmini::bake {

std::vector<Vec3f> read_reference_map(const std::string& path, const Mesh& mesh, int viewpoints) {
  const Mesh ref = read_bakeshop(path);
  const std::size_t nv = mesh.positions.size(), n = static_cast<std::size_t>(viewpoints);
  if (ref.positions.size() != nv)
    throw InputError(path, 0,
                     "reference has " + std::to_string(ref.positions.size()) +
                         " vertices, the scene has " + std::to_string(nv));
  if (ref.viewpoints.empty())
    throw InputError(path, 0, "reference has no viewpoint lines (a raw scene, not a baked map)");
  for (std::size_t v = 0; v < nv; ++v) {
    const Vec3d a = mesh.positions[v], b = ref.positions[v];
    const double scale = 1.0 + std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)});
    if (std::fabs(a.x - b.x) > 1e-6 * scale || std::fabs(a.y - b.y) > 1e-6 * scale ||
        std::fabs(a.z - b.z) > 1e-6 * scale)
      throw InputError(path, 0, "vertex " + std::to_string(v) + " is not where the scene has it");
    const std::size_t count = ref.viewpoints.offsets[v + 1] - ref.viewpoints.offsets[v];
    if (count != n)
      throw InputError(path, 0,
                       "vertex " + std::to_string(v) + " has " + std::to_string(count) +
                           " viewpoints, the bake has N = " + std::to_string(n));
  }
  // Every vertex of a baked map has the same directions: check them all once per vertex.
  std::vector<Vec3f> dirs(n);
  for (std::size_t i = 0; i < n; ++i)
    dirs[i] = Vec3f(fibonacci_point(static_cast<int>(i), viewpoints));
  std::vector<Vec3f> colors(nv * n);
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t first = ref.viewpoints.offsets[v];
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3f d = ref.viewpoints.dirs[first + i], e = dirs[i];
      if (std::fabs(d.x - e.x) > 1e-4f || std::fabs(d.y - e.y) > 1e-4f ||
          std::fabs(d.z - e.z) > 1e-4f)
        throw InputError(path, 0,
                         "viewpoint " + std::to_string(i) + " of vertex " + std::to_string(v) +
                             " is not the bake's Fibonacci direction " + std::to_string(i) +
                             " of N = " + std::to_string(n));
      colors[v * n + i] = ref.viewpoints.colors[first + i];
    }
  }
  return colors;
}

MapErrors compare_maps(const std::vector<Vec3f>& map, const std::vector<std::int64_t>& offset,
                       const std::vector<Vec3f>& reference, int viewpoints) {
  MapErrors e;
  const std::size_t nv = offset.size() - 1, n = static_cast<std::size_t>(viewpoints);
  double abs_sum = 0, sq_sum = 0, rel_sum = 0, ref_sum = 0, vd_sq = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    const bool single = offset[v + 1] - offset[v] == 1;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3f a = map[static_cast<std::size_t>(offset[v]) + (single ? 0 : i)];
      const Vec3f b = reference[v * n + i];
      const double ca[3] = {a.x, a.y, a.z}, cb[3] = {b.x, b.y, b.z};
      for (int c = 0; c < 3; ++c) {
        const double d = ca[c] - cb[c];
        abs_sum += std::fabs(d);
        sq_sum += d * d;
        rel_sum += d * d / (cb[c] * cb[c] + 1e-2);
        ref_sum += cb[c];
        e.max_abs = std::max(e.max_abs, std::fabs(d));
        if (!single) vd_sq += d * d;
      }
      if (!single) ++e.view_dependent;
    }
  }
  e.entries = static_cast<std::int64_t>(nv * n);
  const double values = 3.0 * static_cast<double>(e.entries);
  if (values > 0) {
    e.mean_abs = abs_sum / values;
    e.rmse = std::sqrt(sq_sum / values);
    e.rel_mse = rel_sum / values;
    e.mean_reference = ref_sum / values;
  }
  if (e.view_dependent > 0) e.view_dependent_rmse = std::sqrt(vd_sq / (3.0 * e.view_dependent));
  return e;
}

}  // namespace rtmini::bake
