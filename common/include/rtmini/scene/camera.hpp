#pragma once
// Pinhole / thin-lens camera with a moving centre of projection: depth of field by
// sampling the lens disk and aiming at the focal-plane point of the pinhole ray, and
// motion blur by moving the camera along its velocity over the shutter interval
// (distribution seed: "depth of field" and "motion blur" sections; Cook et al. 1984).
// Shared by sketchtrace and `bake render`, so both see a scene through the same pixels.
#include "rtmini/geometry/ray.hpp"
#include "rtmini/io/scene_file.hpp"

namespace rtmini {

struct DeviceCamera {
  Vec3 position, forward, right, up;  // right/up scaled to the image-plane half extents
  Vec3 velocity;
  Real lens_radius = 0;
  Real focus_distance = 1;
  Real shutter_open = 0, shutter_close = 0;
  int width = 1, height = 1;

  // Continuous pixel coordinates (x right, y down, pixel centres at +0.5); lens
  // sample (lu, lv) in [0,1)^2 and time sample tu in [0,1).
  KOKKOS_INLINE_FUNCTION Ray generate(Real px, Real py, Real lu, Real lv, Real tu, bool lens,
                                      bool motion) const {
    const Real sx = Real(2) * px / Real(width) - Real(1);
    const Real sy = Real(1) - Real(2) * py / Real(height);
    Ray ray;
    ray.dir = normalize(forward + right * sx + up * sy);
    ray.org = position;
    ray.time = shutter_open + (shutter_close - shutter_open) * tu;
    if (motion) ray.org = ray.org + velocity * ray.time;
    if (lens && lens_radius > Real(0)) {
      // Focal-plane point of the pinhole ray, then aim from a point on the lens disk.
      const Real t_focus = focus_distance / dot(ray.dir, forward);
      const Vec3 focal = ray.org + ray.dir * t_focus;
      Real dx, dy;
      concentric_disk(lu, lv, dx, dy);
      const Vec3 rn = normalize(right), un = normalize(up);
      ray.org = ray.org + (rn * dx + un * dy) * lens_radius;
      ray.dir = normalize(focal - ray.org);
    }
    return ray;
  }

  // Shirley-Chiu concentric map of the unit square to the unit disk (area preserving,
  // keeps strata compact so stratified lens samples stay stratified).
  KOKKOS_INLINE_FUNCTION static void concentric_disk(Real u, Real v, Real& x, Real& y) {
    const Real a = Real(2) * u - Real(1), b = Real(2) * v - Real(1);
    if (a == Real(0) && b == Real(0)) {
      x = y = Real(0);
      return;
    }
    const Real quarter_pi = Real(math::kPi / 4);
    Real r, phi;
    if (math::fabs(a) > math::fabs(b)) {
      r = a;
      phi = quarter_pi * (b / a);
    } else {
      r = b;
      phi = Real(2) * quarter_pi - quarter_pi * (a / b);
    }
    x = r * math::cos(phi);
    y = r * math::sin(phi);
  }
};

// Basis from position/look_at/up and a vertical field of view; aperture is the
// lens diameter, a zero focus distance means "focus on look_at".
DeviceCamera make_camera(const CameraDesc& desc, int width, int height);

// The default view of a scene without a camera: looks at the bounds' centre from the
// front-right-above (y up), far enough that the bounding sphere fills the vertical field of
// view with 10 % margin.
CameraDesc frame_bounds(const Vec3d& lo, const Vec3d& hi, double fov_deg);

}  // namespace rtmini
