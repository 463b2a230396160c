#pragma once
// Small scenes for the AO tests.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "ao_scene.hpp"
#include "rtmini/scene/primitives.hpp"

namespace rtmini::ao::test {

// A file's whole contents (the outputs the tests read back).
inline std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A disk of radius r in the plane z = z0 as a fan of `segments` triangles.
inline Mesh disk_mesh(double r, double z0, int segments) {
  Mesh m;
  m.positions.push_back({0.0, 0.0, z0});
  for (int i = 0; i < segments; ++i) {
    const double a = 2.0 * math::kPi * i / segments;
    m.positions.push_back({r * std::cos(a), r * std::sin(a), z0});
  }
  for (int i = 0; i < segments; ++i) {
    Face f;
    f.v = {0, 1 + i, 1 + (i + 1) % segments, -1};
    m.faces.push_back(f);
  }
  return m;
}

inline Mesh quad_mesh(const Vec3d& corner, const Vec3d& u, const Vec3d& v) {
  Mesh m;
  append_quad(m, corner, u, v, -1, 0);
  return m;
}

inline Mesh grid_mesh(const Vec3d& corner, const Vec3d& u, const Vec3d& v, int n) {
  Mesh m;
  append_grid(m, corner, u, v, n, n, -1, 0);
  return m;
}

inline int add_instance(AoScene& scene, const Mesh& mesh, const AffineD& xform = AffineD{},
                        bool blocker = false) {
  scene.meshes.push_back(make_ao_mesh(mesh, "test"));
  AoInstance inst;
  inst.mesh = static_cast<int>(scene.meshes.size()) - 1;
  inst.xform = xform;
  inst.blocker = blocker;
  scene.instances.push_back(inst);
  return static_cast<int>(scene.instances.size()) - 1;
}

}  // namespace rtmini::ao::test
