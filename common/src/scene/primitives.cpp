#include "rtmini/scene/primitives.hpp"

#include <cmath>
#include <map>
#include <utility>

namespace rtmini {

namespace {
int add_vertex(Mesh& m, const Vec3d& p) {
  m.positions.push_back(p);
  return static_cast<int>(m.positions.size()) - 1;
}
void add_face(Mesh& m, std::initializer_list<int> v, int material, int object) {
  Face f;
  int k = 0;
  for (int i : v) f.v[k++] = i;
  f.count = k;
  f.material = material;
  f.object = object;
  m.faces.push_back(f);
}
// Callers number objects themselves (one per primitive, or several primitives per object);
// missing names up to `object` are filled in so every face's object index is valid.
void ensure_object(Mesh& m, int object) {
  while (static_cast<int>(m.objects.size()) <= object)
    m.objects.push_back("object" + std::to_string(m.objects.size()));
}
}  // namespace

void append_icosphere(Mesh& mesh, const Vec3d& center, double radius, int level, int material,
                      int object) {
  ensure_object(mesh, object);
  // The icosahedron from three orthogonal golden rectangles; each level splits every triangle
  // in four and pushes the new vertices onto the sphere. A shared edge's midpoint is made once
  // (the `mid` map), so the mesh stays watertight and its vertex count 10 * 4^level + 2.
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3d> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                          {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                          {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& q : p) q = normalize(q);
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back(normalize((p[a] + p[b]) * 0.5));
      const int id = static_cast<int>(p.size()) - 1;
      mid.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(f.size() * 4);
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]),
                c = midpoint(tri[2], tri[0]);
      next.push_back({tri[0], a, c});
      next.push_back({tri[1], b, a});
      next.push_back({tri[2], c, b});
      next.push_back({a, b, c});
    }
    f.swap(next);
  }
  const int base = static_cast<int>(mesh.positions.size());
  for (const auto& q : p) add_vertex(mesh, center + q * radius);
  for (const auto& tri : f)
    add_face(mesh, {base + tri[0], base + tri[1], base + tri[2]}, material, object);
}

void append_quad(Mesh& mesh, const Vec3d& corner, const Vec3d& u, const Vec3d& v, int material,
                 int object) {
  append_grid(mesh, corner, u, v, 1, 1, material, object);
}

void append_grid(Mesh& mesh, const Vec3d& corner, const Vec3d& u, const Vec3d& v, int nu, int nv,
                 int material, int object) {
  ensure_object(mesh, object);
  const int base = static_cast<int>(mesh.positions.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i)
      add_vertex(mesh, corner + u * (double(i) / nu) + v * (double(j) / nv));
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = base + j * (nu + 1) + i;
      add_face(mesh, {a, a + 1, a + nu + 2, a + nu + 1}, material, object);
    }
}

void append_box(Mesh& mesh, const Vec3d& lo, const Vec3d& hi, int material, int object,
                bool inward) {
  ensure_object(mesh, object);
  const int base = static_cast<int>(mesh.positions.size());
  for (int i = 0; i < 8; ++i)
    add_vertex(mesh, {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  // Outward-wound quads of the unit cube's corners (bit 0 = x, bit 1 = y, bit 2 = z).
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  // inward: the same quads reversed, so the normals face into the box (a room's walls).
  for (const auto& f : q) {
    if (inward)
      add_face(mesh, {base + f[0], base + f[3], base + f[2], base + f[1]}, material, object);
    else
      add_face(mesh, {base + f[0], base + f[1], base + f[2], base + f[3]}, material, object);
  }
}

void append_fan(Mesh& mesh, const Vec3d& center, double radius, double angle, int count,
                int material, int object) {
  ensure_object(mesh, object);
  const int apex = add_vertex(mesh, center);
  for (int i = 0; i <= count; ++i) {
    const double a = angle * i / count;
    add_vertex(mesh, center + Vec3d(std::cos(a), std::sin(a), 0.0) * radius);
  }
  for (int i = 0; i < count; ++i)
    add_face(mesh, {apex, apex + 1 + i, apex + 2 + i}, material, object);
}

}  // namespace rtmini
