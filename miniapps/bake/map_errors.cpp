#include "map_errors.hpp"

#include <algorithm>
#include <cmath>

#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/sampling/fibonacci.hpp"

namespace rtmini::bake {

MapErrors errors_from_sums(const ErrorSums& s) {
  MapErrors e;
  e.entries = s.entries;
  e.view_dependent = s.view_dependent;
  e.max_abs = s.max_abs;
  const double values = 3.0 * static_cast<double>(s.entries);
  if (values > 0) {
    e.mean_abs = s.abs / values;
    e.rmse = std::sqrt(s.sq / values);
    e.rel_mse = s.rel / values;
    e.mean_reference = s.ref / values;
  }
  if (s.view_dependent > 0)
    e.view_dependent_rmse = std::sqrt(s.view_dependent_sq / (3.0 * double(s.view_dependent)));
  if (s.entries > s.view_dependent)
    e.view_independent_rmse = std::sqrt(std::max(0.0, s.sq - s.view_dependent_sq) /
                                        (3.0 * double(s.entries - s.view_dependent)));
  return e;
}

ReferenceMap read_reference_map(const std::string& path, const Mesh& mesh) {
  const Mesh ref = read_bakeshop(path);
  const std::size_t nv = mesh.positions.size();
  if (ref.positions.size() != nv)
    throw InputError(path, 0,
                     "reference has " + std::to_string(ref.positions.size()) +
                         " vertices, the scene has " + std::to_string(nv));
  if (ref.viewpoints.empty())
    throw InputError(path, 0, "reference has no viewpoint lines (a raw scene, not a baked map)");
  if (ref.viewpoints.hemisphere)
    throw InputError(path, 1, "reference is a hemisphere map: compare with a full-sphere map");
  const std::size_t n = ref.viewpoints.offsets[1] - ref.viewpoints.offsets[0];
  if (n == 0) throw InputError(path, 0, "vertex 0 of the reference has no viewpoints");
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
                           " viewpoints, vertex 0 has " + std::to_string(n));
  }
  ReferenceMap out;
  out.viewpoints = static_cast<int>(n);
  std::vector<Vec3f> dirs(n);
  for (std::size_t i = 0; i < n; ++i)
    dirs[i] = Vec3f(fibonacci_point(static_cast<int>(i), out.viewpoints));
  out.colors.resize(nv * n);
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
      out.colors[v * n + i] = ref.viewpoints.colors[first + i];
    }
  }
  return out;
}

MapErrors compare_stored(const std::vector<Vec3f>& map, const std::vector<std::int64_t>& offset,
                         const ReferenceMap& reference) {
  ErrorSums s;
  const std::size_t nv = offset.size() - 1, n = static_cast<std::size_t>(reference.viewpoints);
  for (std::size_t v = 0; v < nv; ++v) {
    const bool single = offset[v + 1] - offset[v] == 1;
    for (std::size_t i = 0; i < n; ++i)
      add_error(s, Vec3(map[static_cast<std::size_t>(offset[v]) + (single ? 0 : i)]),
                Vec3(reference.colors[v * n + i]), !single);
  }
  return errors_from_sums(s);
}

}  // namespace rtmini::bake
