#include "baked_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/bakeshop_binary.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/sampling/fibonacci.hpp"
#include "rtmini/sampling/fibonacci_lookup.hpp"

namespace rtmini::bake {
namespace {

// The baker writes its float Fibonacci directions in shortest round-trip form, so a genuine
// map matches to the last bit; the tolerance only admits maps written by other tools.
constexpr float kDirectionTolerance = 1e-5f;

bool ends_with(const std::string& s, const char* suffix) {
  const std::size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  std::string tail = s.substr(s.size() - n);
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return tail == suffix;
}

bool same_bits(const Vec3f& a, const Vec3f& b) { return std::memcmp(&a, &b, sizeof(Vec3f)) == 0; }

}  // namespace

BakedMapHost read_baked_map(const std::string& path) {
  if (ends_with(path, ".bsb")) return make_baked_map(read_bakeshop_binary(path), path, false);
  return make_baked_map(read_bakeshop(path), path, true);
}

BakedMapHost make_baked_map(Mesh mesh, const std::string& path, bool text_lines) {
  BakedMapHost map;
  const ViewpointColors& vc = mesh.viewpoints;
  const std::size_t nv = mesh.positions.size();
  if (vc.empty())
    throw InputError(path, 0,
                     "no viewpoint colours: a raw scene, not a baked map (bake it first: bake " +
                         path + " -o MAP.bs)");
  // Line of vertex v (text form: each vertex line is followed by its viewpoint lines).
  const long header = vc.hemisphere ? 1 : 0;  // the "# hemisphere" line
  auto where = [&](std::size_t v, long viewpoint) {
    return text_lines ? header + static_cast<long>(1 + v + vc.offsets[v]) +
                            (viewpoint >= 0 ? 1 + viewpoint : 0)
                      : 0L;
  };
  auto what = [&](std::size_t v, const std::string& reason) {
    return text_lines ? reason : "vertex " + std::to_string(v) + ": " + reason;
  };
  std::vector<char> used(nv, 0);
  for (const Face& f : mesh.faces)
    for (int k = 0; k < f.count; ++k) used[f.v[k]] = 1;
  std::size_t n = 0;
  for (std::size_t v = 0; v < nv; ++v) n = std::max(n, vc.offsets[v + 1] - vc.offsets[v]);
  // A hemisphere map stores the first N/2 of the N Fibonacci points (in each vertex's frame).
  map.hemisphere = vc.hemisphere;
  map.viewpoints = static_cast<int>(vc.hemisphere ? 2 * n : n);
  std::vector<Vec3f> fib(n);
  for (std::size_t j = 0; j < n; ++j)
    fib[j] = Vec3f(fibonacci_point(static_cast<int>(j), map.viewpoints));

  map.color_offset.assign(nv + 1, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t first = vc.offsets[v], count = vc.offsets[v + 1] - first;
    if (count == 0 && !used[v]) {  // a stray vertex on no face: never seen
      map.colors.emplace_back(0.f);
      map.color_offset[v + 1] = static_cast<std::int64_t>(map.colors.size());
      continue;
    }
    if (count != n)
      throw InputError(
          path, where(v, -1),
          what(v, "vertex has " + std::to_string(count) + " viewpoints, the map's other vertices " +
                      std::to_string(n) + " (a baked map has N per vertex)"));
    for (std::size_t j = 0; j < n; ++j) {
      const Vec3f d = vc.dirs[first + j];
      const Vec3f e = fib[j];
      if (!(std::fabs(d.x - e.x) <= kDirectionTolerance &&
            std::fabs(d.y - e.y) <= kDirectionTolerance &&
            std::fabs(d.z - e.z) <= kDirectionTolerance))
        throw InputError(
            path, where(v, static_cast<long>(j)),
            what(v, "viewpoint " + std::to_string(j) + " is not the baker's Fibonacci direction " +
                        std::to_string(j) + " of " + std::to_string(map.viewpoints) +
                        (vc.hemisphere ? " (hemisphere map: in the vertex's frame)" : "")));
      const Vec3f c = vc.colors[first + j];
      if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z)))
        throw InputError(path, where(v, static_cast<long>(j)), what(v, "colour is not finite"));
    }
    bool uniform = true;
    for (std::size_t j = 1; j < n && uniform; ++j)
      uniform = same_bits(vc.colors[first + j], vc.colors[first]);
    if (uniform) {
      map.colors.push_back(vc.colors[first]);
    } else {
      map.colors.insert(map.colors.end(), vc.colors.begin() + first, vc.colors.begin() + first + n);
      ++map.view_dependent_vertices;
    }
    map.color_offset[v + 1] = static_cast<std::int64_t>(map.colors.size());
  }
  mesh.viewpoints = ViewpointColors();
  map.mesh = std::move(mesh);
  if (map.mesh.faces.empty()) throw InputError(path, 0, "the map has no faces");
  if (map.hemisphere) map.normal = prepare_bake_scene(map.mesh, static_cast<int>(n)).normal;
  return map;
}

namespace {
template <class T>
Kokkos::View<T*, MemSpace> upload(const char* label, const std::vector<T>& host) {
  return compat::upload<MemSpace>(label, host);
}
}  // namespace

BakedMapDevice upload_baked_map(const BakedMapHost& map, bvh::BuildQuality quality) {
  BakedMapDevice d;
  d.mesh = upload_mesh(map.mesh, quality);
  d.color_offset = upload("rtmini::bake::render::color_offset", map.color_offset);
  d.colors = upload("rtmini::bake::render::colors", map.colors);
  d.viewpoints = map.viewpoints;
  d.hemisphere.points = fibonacci_points<MemSpace>(map.viewpoints);
  if (map.hemisphere) {
    d.hemisphere.normal = upload("rtmini::bake::render::normal", map.normal);
    d.hemisphere.stored = map.viewpoints / 2;
  }
  return d;
}

}  // namespace rtmini::bake
