#pragma once
// The truth a baked map approximates (issue 7, "error of a baked map"): the colour of vertex v
// seen along viewpoint direction d with the bake's light transport, traced directly instead of
// read from a map. K iterations of the bake are K nested mirror lookups; the lookup of a
// previous map at a hit mixes the hit face's three vertex colours, each seen along the same
// mirror direction. Tracing that recursion exactly (one mirror ray per reflective vertex on the
// path, the base colours at the leaves) gives the map that N -> infinity viewpoints converge
// to, so its difference from a baked map is the viewpoint-lookup error alone (plus the base
// colours' shadow noise when the reference has more shadow samples).
#include <cstdint>

#include "bake_scene.hpp"
#include "map_reader.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/geometry/offset.hpp"

namespace rtmini::bake {

// Deepest reference: the depth-first stack holds at most 2 K + 1 nodes (three children per
// expanded node). The cost is up to 3^K mirror rays per colour, so K beyond ~12 is impractical.
inline constexpr int kMaxReferenceIterations = 16;

struct ReferenceTracer {
  bvh::Bvh<MemSpace> accel;
  Kokkos::View<int* [3], MemSpace> tri_vertices;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;
  Kokkos::View<Vec3*, MemSpace> positions, normal, reflective;
  Kokkos::View<Vec3*, MemSpace> base;  // per vertex: emission + direct light (iteration 0)
  Vec3 background;
  Real coordinate_bound;   // DeviceMesh::coordinate_bound, for offset_ray_origin
  bool two_sided = false;  // BakeConfig::two_sided (mirror_normal)

  // Colour of vertex v along camera direction d after `iterations` mirror iterations; adds the
  // mirror rays traced to `rays`. A vertex without a reflective part has its base colour.
  KOKKOS_INLINE_FUNCTION Vec3 radiance(int v, const Vec3& d, int iterations,
                                       std::int64_t& rays) const {
    struct Node {
      int vertex, depth;
      Vec3 dir, weight;
    };
    Node stack[2 * kMaxReferenceIterations + 1];
    int top = 0;
    stack[top++] = Node{v, iterations, d, Vec3(Real(1))};
    Vec3 sum(Real(0));
    while (top > 0) {
      const Node node = stack[--top];
      sum += node.weight * base(node.vertex);
      // The map keeps one colour for a vertex without a reflective part: its base colour.
      if (node.depth == 0 || color_offset(node.vertex + 1) - color_offset(node.vertex) == 1)
        continue;
      const Vec3 n = mirror_normal(node.dir, normal(node.vertex), two_sided);
      const Vec3 weight = node.weight * reflective(node.vertex);
      Ray ray;
      ray.org = offset_ray_origin(positions(node.vertex), n, coordinate_bound);
      ray.dir = mirror_direction(node.dir, n);
      const Hit hit = bvh::closest_hit(accel, ray);
      ++rays;
      if (hit.prim < 0) {
        sum += weight * background;
        continue;
      }
      const Real w[3] = {Real(1) - hit.u - hit.v, hit.u, hit.v};
      for (int k = 0; k < 3; ++k)
        stack[top++] = Node{tri_vertices(hit.prim, k), node.depth - 1, ray.dir, weight * w[k]};
    }
    return sum;
  }
};

}  // namespace rtmini::bake
