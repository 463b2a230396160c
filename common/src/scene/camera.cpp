#include "rtmini/scene/camera.hpp"

#include <algorithm>
#include <cmath>

namespace rtmini {

DeviceCamera make_camera(const CameraDesc& desc, int width, int height) {
  DeviceCamera c;
  const Vec3d fwd = normalize(desc.look_at - desc.position);
  // Looking straight along `up` leaves the roll undefined (zero cross product); any axis
  // perpendicular to the view works then, and z is (a view along y is the common case).
  Vec3d right = normalize(cross(fwd, desc.up));
  if (length(right) == 0.0) right = normalize(cross(fwd, Vec3d(0.0, 0.0, 1.0)));
  const Vec3d up = cross(right, fwd);
  const double half_h = std::tan(0.5 * desc.fov_deg * math::kPi / 180.0);
  const double half_w = half_h * static_cast<double>(width) / static_cast<double>(height);
  c.position = Vec3(desc.position);
  c.forward = Vec3(fwd);
  // right and up carry the half extent of the image plane at distance 1 (computed in double,
  // stored in Real), so a ray direction is forward + sx * right + sy * up, no per-ray tan().
  c.right = Vec3(right * half_w);
  c.up = Vec3(up * half_h);
  c.velocity = Vec3(desc.velocity);
  c.lens_radius = static_cast<Real>(0.5 * desc.aperture);
  // Unset focus distance: focus on the look-at point; a camera placed on that point (distance
  // 0) falls back to 1 so the thin-lens maths stays finite.
  const double focus =
      desc.focus_distance > 0.0 ? desc.focus_distance : length(desc.look_at - desc.position);
  c.focus_distance = static_cast<Real>(focus > 0.0 ? focus : 1.0);
  c.shutter_open = static_cast<Real>(desc.shutter_open);
  c.shutter_close = static_cast<Real>(desc.shutter_close);
  c.width = width;
  c.height = height;
  return c;
}

CameraDesc frame_bounds(const Vec3d& lo, const Vec3d& hi, double fov_deg) {
  CameraDesc c;
  c.fov_deg = fov_deg;
  const Vec3d center = (lo + hi) * 0.5;
  const double radius = std::max(0.5 * length(hi - lo), 1e-6);
  // The bounding sphere fits in the view cone at radius / sin(fov/2), plus a 10 % margin; the
  // fixed oblique direction shows three faces of a box, never an edge-on wall.
  const double dist = 1.1 * radius / std::sin(0.5 * fov_deg * math::kPi / 180.0);
  c.look_at = center;
  c.position = center + normalize(Vec3d(0.35, 0.45, 1.0)) * dist;
  c.up = Vec3d(0.0, 1.0, 0.0);
  return c;
}

}  // namespace rtmini
