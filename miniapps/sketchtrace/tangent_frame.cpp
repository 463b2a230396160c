#include "tangent_frame.hpp"

#include <cmath>
#include <map>
#include <tuple>

namespace rtmini::sketch {
namespace {

// dp/du, dp/dv of one triangle from its corners and texture coordinates; false when the
// texture mapping is degenerate (zero uv area).
bool triangle_derivatives(const Vec3d p[3], const TexCoord uv[3], Vec3d& dpdu, Vec3d& dpdv) {
  const Vec3d e1 = p[1] - p[0], e2 = p[2] - p[0];
  const double du1 = uv[1].u - uv[0].u, dv1 = uv[1].v - uv[0].v;
  const double du2 = uv[2].u - uv[0].u, dv2 = uv[2].v - uv[0].v;
  const double det = du1 * dv2 - du2 * dv1;
  if (!(std::fabs(det) > 1e-20)) return false;
  dpdu = (e1 * dv2 - e2 * dv1) / det;
  dpdv = (e2 * du1 - e1 * du2) / det;
  return true;
}

double corner_angle(const Vec3d& at, const Vec3d& a, const Vec3d& b) {
  const Vec3d x = a - at, y = b - at;
  const double lx = length(x), ly = length(y);
  if (!(lx > 0 && ly > 0)) return 0;
  return std::acos(std::fmax(-1.0, std::fmin(1.0, dot(x, y) / (lx * ly))));
}

}  // namespace

CornerTangents corner_tangents(const std::vector<Vec3d>& positions,
                               const std::vector<std::array<int, 3>>& tris,
                               const std::vector<std::array<int, 3>>& uv_ids,
                               const std::vector<TexCoord>& texcoords,
                               const std::vector<std::array<int, 3>>& normal_ids,
                               const std::vector<Vec3>& normals) {
  const std::size_t n = tris.size();
  CornerTangents out;
  out.tangent.assign(n, {Vec3(Real(0)), Vec3(Real(0)), Vec3(Real(0))});
  out.sign.assign(n, 1.f);
  // A MikkTSpace vertex: same position, texture coordinate, normal and handedness.
  using Key = std::tuple<int, int, int, int>;
  std::map<Key, Vec3d> sum;
  std::vector<char> mapped(n, 0);
  std::vector<Vec3d> face_normal(n);
  for (std::size_t t = 0; t < n; ++t) {
    if (uv_ids[t][0] < 0 || uv_ids[t][1] < 0 || uv_ids[t][2] < 0) continue;
    const Vec3d p[3] = {positions[tris[t][0]], positions[tris[t][1]], positions[tris[t][2]]};
    const TexCoord uv[3] = {texcoords[uv_ids[t][0]], texcoords[uv_ids[t][1]],
                            texcoords[uv_ids[t][2]]};
    Vec3d dpdu, dpdv;
    if (!triangle_derivatives(p, uv, dpdu, dpdv)) continue;
    face_normal[t] = cross(p[1] - p[0], p[2] - p[0]);
    out.sign[t] = dot(cross(face_normal[t], dpdu), dpdv) < 0 ? -1.f : 1.f;
    mapped[t] = 1;
    const Vec3d unit = normalize(dpdu);
    for (int k = 0; k < 3; ++k) {
      const double w = corner_angle(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
      const Key key{tris[t][k], uv_ids[t][k], normal_ids[t][k], out.sign[t] < 0 ? -1 : 1};
      auto [it, inserted] = sum.emplace(key, Vec3d(0.0));
      (void)inserted;
      it->second += unit * w;
    }
  }
  for (std::size_t t = 0; t < n; ++t) {
    if (!mapped[t]) continue;
    for (int k = 0; k < 3; ++k) {
      const Key key{tris[t][k], uv_ids[t][k], normal_ids[t][k], out.sign[t] < 0 ? -1 : 1};
      Vec3d normal = Vec3d(normals[normal_ids[t][k]]);
      if (!(dot(normal, normal) > 0)) normal = normalize(face_normal[t]);
      const Vec3d acc = sum[key];
      const Vec3d ortho = acc - normal * dot(normal, acc);
      if (dot(ortho, ortho) > 1e-30) out.tangent[t][k] = Vec3(normalize(ortho));
    }
  }
  return out;
}

}  // namespace rtmini::sketch
