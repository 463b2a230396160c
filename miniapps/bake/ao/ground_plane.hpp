#pragma once
// The virtual ground plane blocker of the baking sample: an axis-aligned square
// below the receivers (above them for a negative axis), tested analytically.
#include "rtmini/geometry/ray.hpp"

namespace rtmini::ao {

struct GroundPlane {
  int enabled = 0;
  int axis = 1;                         // normal axis 0..2
  Real level = 0;                       // plane coordinate along axis
  Real lo[2] = {0, 0}, hi[2] = {0, 0};  // square extent along the other two axes (axis+1, axis+2)

  // Two-sided hit with t in [ray.tmin, ray.tmax].
  KOKKOS_INLINE_FUNCTION bool hit(const Ray& ray) const {
    const Real d = ray.dir[axis];
    if (!enabled || d == Real(0)) return false;
    const Real t = (level - ray.org[axis]) / d;
    if (!(t >= ray.tmin && t <= ray.tmax)) return false;
    const int a1 = axis == 2 ? 0 : axis + 1, a2 = axis == 0 ? 2 : axis - 1;
    const Real p1 = ray.org[a1] + t * ray.dir[a1], p2 = ray.org[a2] + t * ray.dir[a2];
    return p1 >= lo[0] && p1 <= hi[0] && p2 >= lo[1] && p2 <= hi[1];
  }
};

// setup_axis 0..5 = +x +y +z -x -y -z (the up direction). With E the largest
// extent of the receivers' bounds: the plane lies offset * E below the bounds
// (beyond their minimum along +axis, their maximum along -axis), and is a square
// of side scale * E centred on the bounds.
inline GroundPlane make_ground_plane(const Vec3d& lo, const Vec3d& hi, int setup_axis, double scale,
                                     double offset) {
  GroundPlane g;
  g.enabled = 1;
  g.axis = setup_axis % 3;
  const double extent = max_component(hi - lo);
  const Vec3d c = (lo + hi) * 0.5;
  g.level = static_cast<Real>(setup_axis < 3 ? lo[g.axis] - offset * extent
                                             : hi[g.axis] + offset * extent);
  const int a1 = g.axis == 2 ? 0 : g.axis + 1, a2 = g.axis == 0 ? 2 : g.axis - 1;
  const double half = 0.5 * scale * extent;
  g.lo[0] = static_cast<Real>(c[a1] - half);
  g.hi[0] = static_cast<Real>(c[a1] + half);
  g.lo[1] = static_cast<Real>(c[a2] - half);
  g.hi[1] = static_cast<Real>(c[a2] + half);
  return g;
}

}  // namespace rtmini::ao
