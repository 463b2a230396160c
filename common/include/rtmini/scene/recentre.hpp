#pragma once
// Where the kernels' coordinate frame sits and whether the working precision can hold the
// scene there (geometry/offset.hpp argues the scheme). Host only: the scene is moved in double,
// before anything is rounded to Real.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "rtmini/geometry/vec.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini {

struct Bounds3d {
  Vec3d lo{std::numeric_limits<double>::infinity()};
  Vec3d hi{-std::numeric_limits<double>::infinity()};

  void add(const Vec3d& p) {
    lo = vmin(lo, p);
    hi = vmax(hi, p);
  }
  bool empty() const { return !(lo.x <= hi.x); }
  // The kernels' frame: the box centre goes to the origin (zero for an empty box).
  Vec3d centre() const { return empty() ? Vec3d(0.0) : (lo + hi) * 0.5; }
  // The largest coordinate magnitude once `origin` is subtracted.
  double bound_about(const Vec3d& origin) const {
    if (empty()) return 0.0;
    return std::max(max_component(vabs(lo - origin)), max_component(vabs(hi - origin)));
  }
};

inline Bounds3d bounds_of(const std::vector<Vec3d>& points) {
  Bounds3d b;
  for (const Vec3d& p : points) b.add(p);
  return b;
}

// The range of coordinate bounds M (largest |coordinate| about the frame's origin) that Real
// holds: the watertight test forms products of three coordinate differences (~M^3), squared
// lengths and areas need M^2, so M^3 must stay inside the normal range, with a factor 100 of
// headroom for the sums and the light/area terms on top. Above, a triangle's unit normal
// (triangle_normal, in Real on the device) squares the cross product of two edges, ~(2M)^4:
// M^4 must stay below the largest Real with a factor 10^4 of headroom (float scenes of
// half-extent 1e10 rendered 77 % dark before this bound; results/accuracy/extremes.md), and
// (2M)^4 must stay above the smallest normal Real with a factor 10^4 (float AO at half-extent
// 1e-10 read 1 % off: the squared length went subnormal). float: about 3e-9 .. 4e8; double:
// about 1e-76 .. 1e76.
inline double min_coordinate_bound() {
  const double bottom = double(std::numeric_limits<Real>::min());
  return std::max(100.0 * std::cbrt(bottom), 10.0 * std::sqrt(std::sqrt(bottom)));
}
inline double max_coordinate_bound() {
  const double top = double(std::numeric_limits<Real>::max());
  return std::min(0.01 * std::cbrt(top), 0.1 * std::sqrt(std::sqrt(top)));
}
// Inputs are parsed into double and moved in double: a scene whose extent is below 2^-32 of its
// distance from the origin had at most 2^20 distinct input coordinates across it (about 1e-6
// of its size) before any rendering started. Independent of Real.
constexpr double kMaxDistanceOverExtent = 4294967296.0;  // 2^32

// Exit 2 (InputError "where: reason") when the precision cannot represent the scene in bounds
// `b` (world coordinates) once moved to `origin`.
inline void check_representable(const Bounds3d& b, const Vec3d& origin, const std::string& where) {
  if (b.empty()) return;
  const double m = b.bound_about(origin);
  const double extent = max_component(b.hi - b.lo);
  const double distance = max_component(vabs(origin));
  const char* real = sizeof(Real) == 4 ? "float" : "double";
  std::ostringstream why;
  why.precision(3);
  if (!(extent > 0.0)) {
    why << "the scene has zero extent";
  } else if (m < min_coordinate_bound() || m > max_coordinate_bound()) {
    why << "scene half-extent " << m << " is outside what " << real << " represents ("
        << min_coordinate_bound() << " .. " << max_coordinate_bound()
        << ": products of coordinates leave the normal range)";
  } else if (distance > kMaxDistanceOverExtent * extent) {
    why << "scene extent " << extent << " at distance " << distance
        << " from the origin: the input coordinates (double) resolve under 2^20 steps across it";
  } else {
    return;
  }
  throw InputError(where, 0, why.str() + "; rescale or move the scene");
}

}  // namespace rtmini
