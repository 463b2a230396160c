#pragma once
// Small scenes built in code and a whole-image render helper for the tests.
#include <vector>

#include "render_scene.hpp"
#include "renderer.hpp"
#include "rtmini/scene/primitives.hpp"

namespace rtmini::sketch::test {

inline std::vector<PixelResult> render_all(const HostScene& scene, const RenderSettings& s) {
  const Renderer r(scene, s);
  std::vector<PixelResult> out;
  r.render({{0, 0, s.width, s.height}}, out);
  return out;
}

// A grey Lambertian plane y = 0 of half-size `half` and albedo kd.
inline void add_floor(HostScene& scene, double half, float kd) {
  Material m;
  m.diffuse = Vec3f(kd);
  const int mat = add_scene_material(scene, m);
  const int obj = add_mesh_object(scene, "floor");
  append_quad(scene.mesh, Vec3d(-half, 0, half), Vec3d(2 * half, 0, 0), Vec3d(0, 0, -2 * half), mat,
              obj);
}

inline double luminance(const PixelResult& p) { return (double(p.r) + p.g + p.b) / 3.0; }

}  // namespace rtmini::sketch::test
