#include "affine.hpp"

#include <cmath>

namespace rtmini::ao {

AffineD compose(const AffineD& a, const AffineD& b) {
  AffineD out;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) {
      double s = j == 3 ? a.m[i][3] : 0.0;
      for (int k = 0; k < 3; ++k) s += a.m[i][k] * b.m[k][j];
      out.m[i][j] = s;
    }
  }
  return out;
}

double determinant(const AffineD& a) {
  const auto& m = a.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

AffineD inverse(const AffineD& a) {
  const auto& m = a.m;
  const double inv_det = 1.0 / determinant(a);
  AffineD out;
  // Adjugate of the linear part divided by the determinant.
  out.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * inv_det;
  out.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * inv_det;
  out.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * inv_det;
  out.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * inv_det;
  out.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * inv_det;
  out.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * inv_det;
  out.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * inv_det;
  out.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * inv_det;
  out.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * inv_det;
  const Vec3d t(m[0][3], m[1][3], m[2][3]);
  const Vec3d it = -out.vector(t);
  out.m[0][3] = it.x;
  out.m[1][3] = it.y;
  out.m[2][3] = it.z;
  return out;
}

bool is_identity(const AffineD& a) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j)
      if (a.m[i][j] != (i == j ? 1.0 : 0.0)) return false;
  return true;
}

AffineD make_trs(const Vec3d& translate, const Vec3d& rotate_deg, const Vec3d& scale) {
  constexpr double kDegToRad = math::kPi / 180.0;
  const double cx = std::cos(rotate_deg.x * kDegToRad), sx = std::sin(rotate_deg.x * kDegToRad);
  const double cy = std::cos(rotate_deg.y * kDegToRad), sy = std::sin(rotate_deg.y * kDegToRad);
  const double cz = std::cos(rotate_deg.z * kDegToRad), sz = std::sin(rotate_deg.z * kDegToRad);
  const double r[3][3] = {{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
                          {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
                          {-sy, cy * sx, cy * cx}};
  const double s[3] = {scale.x, scale.y, scale.z};
  AffineD out;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out.m[i][j] = r[i][j] * s[j];
  out.m[0][3] = translate.x;
  out.m[1][3] = translate.y;
  out.m[2][3] = translate.z;
  return out;
}

}  // namespace rtmini::ao
