#include "crease_normals.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace rtmini::sketch {
namespace {

// The triangles around every vertex, as a compressed row list of (triangle, corner).
struct VertexStar {
  std::vector<std::int64_t> begin;             // vertex v owns entries [begin[v], begin[v + 1])
  std::vector<std::pair<int, int>> triangles;  // (triangle, corner k with tri[k] == v)
};

VertexStar vertex_star(std::size_t num_vertices, const std::vector<std::array<int, 3>>& tris) {
  VertexStar s;
  s.begin.assign(num_vertices + 1, 0);
  for (const auto& t : tris)
    for (int v : t) ++s.begin[v + 1];
  std::partial_sum(s.begin.begin(), s.begin.end(), s.begin.begin());
  s.triangles.resize(tris.size() * 3);
  std::vector<std::int64_t> fill(s.begin.begin(), s.begin.end() - 1);
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) s.triangles[fill[tris[t][k]]++] = {static_cast<int>(t), k};
  return s;
}

// Union-find over the few triangles around one vertex.
int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Faces meet smoothly when their normals are at most the crease angle apart; degenerate
// faces (zero normal) meet nothing.
bool meet_smoothly(const Vec3d& na, const Vec3d& nb, double cos_crease) {
  const double la = length(na), lb = length(nb);
  return la > 0 && lb > 0 && dot(na, nb) >= cos_crease * la * lb;
}

}  // namespace

CornerNormals crease_split_normals(const std::vector<Vec3d>& positions,
                                   const std::vector<std::array<int, 3>>& triangles,
                                   double cos_crease) {
  std::vector<Vec3d> face(triangles.size());  // area-weighted (unnormalised cross products)
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& v = triangles[t];
    face[t] = cross(positions[v[1]] - positions[v[0]], positions[v[2]] - positions[v[0]]);
  }
  const VertexStar star = vertex_star(positions.size(), triangles);
  CornerNormals out;
  out.of_corner.resize(triangles.size());
  std::vector<int> parent, group_of_root;
  std::vector<std::pair<int, int>> edges;  // (other vertex of an edge at v, local triangle)
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const std::int64_t b = star.begin[v];
    const int n = static_cast<int>(star.begin[v + 1] - b);
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0);
    // Triangles around v that share an edge (v, w) list the same w: sorting brings them together.
    edges.clear();
    for (int i = 0; i < n; ++i) {
      const auto [t, k] = star.triangles[b + i];
      edges.push_back({triangles[t][(k + 1) % 3], i});
      edges.push_back({triangles[t][(k + 2) % 3], i});
    }
    std::sort(edges.begin(), edges.end());
    for (std::size_t e = 1; e < edges.size(); ++e) {
      if (edges[e].first != edges[e - 1].first) continue;
      const int i = edges[e - 1].second, j = edges[e].second;
      if (!meet_smoothly(face[star.triangles[b + i].first], face[star.triangles[b + j].first],
                         cos_crease))
        continue;
      parent[find_root(parent, i)] = find_root(parent, j);
    }
    // One normal per group, numbered in the order the groups' first triangles appear.
    group_of_root.assign(n, -1);
    for (int i = 0; i < n; ++i) {
      const int r = find_root(parent, i);
      if (group_of_root[r] < 0) {
        group_of_root[r] = static_cast<int>(out.normals.size());
        out.normals.push_back(Vec3d(0.0));
      }
      const auto [t, k] = star.triangles[b + i];
      out.normals[group_of_root[r]] += face[t];
      out.of_corner[t][k] = group_of_root[r];
    }
  }
  for (Vec3d& nrm : out.normals)
    if (length(nrm) > 0) nrm = normalize(nrm);
  return out;
}

}  // namespace rtmini::sketch
