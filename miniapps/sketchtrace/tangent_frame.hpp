#pragma once
// Tangent frames for normal and bump maps. On the host, per-vertex tangents in the
// manner of MikkTSpace: every triangle's dp/du is accumulated, weighted by the corner
// angle, into the vertices it shares position, texture coordinate and shading normal
// with, then made orthogonal to that normal; the handedness sign says whether dp/dv
// runs along +cross(n, t) or against it (mirrored UVs). At a hit the interpolated
// tangent is Gram-Schmidt-orthogonalised against the shading normal again.
#include <array>
#include <vector>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini::sketch {

// A tangent-space basis: t along +u, b along +v, n the shading normal; all unit length.
struct TangentFrame {
  Vec3 t, b, n;
  KOKKOS_INLINE_FUNCTION Vec3 to_world(const Vec3& l) const { return t * l.x + b * l.y + n * l.z; }
  KOKKOS_INLINE_FUNCTION Vec3 to_local(const Vec3& w) const {
    return {dot(w, t), dot(w, b), dot(w, n)};
  }
};

// The frame at a hit: `tangent` (interpolated, not unit) made orthogonal to the unit normal
// `n`; a tangent (anti)parallel to n falls back to any perpendicular.
KOKKOS_INLINE_FUNCTION TangentFrame tangent_frame_at(const Vec3& n, const Vec3& tangent,
                                                     Real sign) {
  TangentFrame f;
  f.n = n;
  Vec3 t = tangent - n * dot(n, tangent);
  const Real len2 = dot(t, t);
  if (!(len2 > Real(1e-20))) {
    t = math::fabs(n.x) < Real(0.9) ? Vec3(Real(1), Real(0), Real(0))
                                    : Vec3(Real(0), Real(1), Real(0));
    t = t - n * dot(n, t);
  }
  f.t = normalize(t);
  f.b = cross(n, f.t) * (sign < Real(0) ? Real(-1) : Real(1));
  return f;
}

// Per-corner tangents of a triangle list: tangent[t][k] (unit, orthogonal to the corner's
// shading normal) and sign[t] (+1 or -1, that of the triangle's dp/du, dp/dv pair). Triangles
// without texture coordinates (uv[t][0] < 0) get a zero tangent and sign +1.
struct CornerTangents {
  std::vector<std::array<Vec3, 3>> tangent;
  std::vector<float> sign;
};

// positions: mesh vertices; tris: vertex ids; uv_ids/texcoords: texture coordinate ids per
// corner (-1 none) and values; normal_ids/normals: shading normal id per corner and values.
CornerTangents corner_tangents(const std::vector<Vec3d>& positions,
                               const std::vector<std::array<int, 3>>& tris,
                               const std::vector<std::array<int, 3>>& uv_ids,
                               const std::vector<TexCoord>& texcoords,
                               const std::vector<std::array<int, 3>>& normal_ids,
                               const std::vector<Vec3>& normals);

}  // namespace rtmini::sketch
