#pragma once
// The last touches every builder gives its tree, as per-element functions so the device
// kernels (build.hpp) and the host SAH build (build_sah.cpp) apply the same arithmetic.
#include "rtmini/bvh/bvh.hpp"

namespace rtmini::bvh {

// Zero-area triangles become the point (a, a, a): the watertight test gives U = V = W = 0
// there, so no ray hits them, whatever rounding the shear adds (issue 7, stability).
KOKKOS_INLINE_FUNCTION Triangle point_if_zero_area(const Triangle& t) {
  return is_zero_area(t.a, t.b, t.c) ? Triangle{t.a, t.a, t.a} : t;
}

// Every child box grows outward by about four float ulps (relative 4.8e-7, plus 1e-30 at zero).
// A ray with a zero direction component whose origin lies exactly in the plane of a box face
// would otherwise get (face - origin) * (1 / 0) = 0 * huge = 0 as that slab's far distance and
// miss a box whose triangles it hits on that face (issue 7); inside a padded box its origin is
// strictly within the slab. The padding is conservative: the triangle test decides every hit.
KOKKOS_INLINE_FUNCTION Real pad_below(Real x) {
  return x - (math::fabs(x) * Real(4.8e-7) + Real(1e-30));
}
KOKKOS_INLINE_FUNCTION Real pad_above(Real x) {
  return x + (math::fabs(x) * Real(4.8e-7) + Real(1e-30));
}

KOKKOS_INLINE_FUNCTION void pad_child_boxes(BvhNode& n) {
  for (int k = 0; k < 2; ++k) {
    if (n.child[k] == kEmptyLeaf) continue;  // its empty box stays empty
    n.lo_x[k] = pad_below(n.lo_x[k]);
    n.lo_y[k] = pad_below(n.lo_y[k]);
    n.lo_z[k] = pad_below(n.lo_z[k]);
    n.hi_x[k] = pad_above(n.hi_x[k]);
    n.hi_y[k] = pad_above(n.hi_y[k]);
    n.hi_z[k] = pad_above(n.hi_z[k]);
  }
}

}  // namespace rtmini::bvh
