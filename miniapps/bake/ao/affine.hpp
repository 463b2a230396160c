#pragma once
// Affine transforms of instances (p' = L p + t), host and device. Host code
// composes and inverts in double; kernels use the Real copy.
#include "rtmini/geometry/vec.hpp"

namespace rtmini::ao {

template <class T>
struct AffineT {
  T m[3][4] = {{T(1), T(0), T(0), T(0)}, {T(0), T(1), T(0), T(0)}, {T(0), T(0), T(1), T(0)}};

  KOKKOS_INLINE_FUNCTION Vec3T<T> vector(const Vec3T<T>& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  KOKKOS_INLINE_FUNCTION Vec3T<T> point(const Vec3T<T>& p) const {
    return vector(p) + Vec3T<T>(m[0][3], m[1][3], m[2][3]);
  }
  template <class U>
  AffineT<U> cast() const {
    AffineT<U> out;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) out.m[i][j] = static_cast<U>(m[i][j]);
    return out;
  }
};

using Affine = AffineT<Real>;
using AffineD = AffineT<double>;

// a * b: apply b first, then a.
AffineD compose(const AffineD& a, const AffineD& b);
// Inverse of an invertible affine map (InputError-free: callers validate the determinant).
AffineD inverse(const AffineD& a);
double determinant(const AffineD& a);
bool is_identity(const AffineD& a);
// Scale, then XYZ Euler rotation (degrees, about x, then y, then z), then translation:
// the order of the scene TOML's [[meshes]] entries (io/scene_file.hpp).
AffineD make_trs(const Vec3d& translate, const Vec3d& rotate_deg, const Vec3d& scale);

}  // namespace rtmini::ao
