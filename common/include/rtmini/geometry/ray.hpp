#pragma once
#include "rtmini/geometry/vec.hpp"

namespace rtmini {

// A ray segment origin + t * dir for t in [tmin, tmax].
struct Ray {
  Vec3 org;
  Vec3 dir;
  Real tmin = Real(0);
  Real tmax = Real(1e30);
  // The instant the ray samples (scene time, between the camera's shutter_open and
  // shutter_close): only moving objects read it (sketchtrace's motion.hpp).
  Real time = Real(0);
};

// Closest-hit record. prim is the triangle index in the caller's original
// numbering (not the BVH's internal order); -1 means no hit. (u, v) are the
// barycentric weights of the triangle's second and third vertex.
struct Hit {
  Real t = Real(1e30);
  Real u = Real(0);
  Real v = Real(0);
  int prim = -1;
  KOKKOS_INLINE_FUNCTION bool valid() const { return prim >= 0; }
};

}  // namespace rtmini
