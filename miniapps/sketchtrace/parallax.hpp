#pragma once
// Parallax occlusion mapping in tangent space with soft self-shadowing (Tatarchuk
// 2006). The height field hangs below the polygon: texel height h in [0, 1] is
// depth 1 - h, the polygon is depth 0 and depth 1 lies `depth_uv` (the height
// scale in texture-coordinate units) below it. The view ray is marched down in
// linear steps (more at grazing angles) until it passes under the surface, and the
// crossing is refined by intersecting the last segment with the surface's chord.
#include "rtmini/geometry/vec.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini::sketch {

inline constexpr int kParallaxMinSteps = 8, kParallaxMaxSteps = 48;
// Steepest view ray followed: below this tangent-space cos the shift is clamped, not infinite.
inline constexpr Real kParallaxMinCos = Real(0.05);
// Soft shadow (Tatarchuk's "penumbra"): visibility = 1 - sharpness x the largest
// depth-weighted blocker height above the light ray.
inline constexpr Real kParallaxShadowSharpness = Real(4);

struct ParallaxHit {
  Real u, v;   // where the view ray meets the height field
  Real depth;  // in [0, 1]
};

// `height(u, v)` returns h in [0, 1]; `view` points from the surface to the eye in the tangent
// frame (t along +u, b along +v, n up), unit length.
template <class Height>
KOKKOS_INLINE_FUNCTION ParallaxHit parallax_occlusion(const Height& height, Real u, Real v,
                                                      const Vec3& view, Real depth_uv) {
  const Real cz = math::fmax(view.z, kParallaxMinCos);
  const Real du = -view.x / cz * depth_uv, dv = -view.y / cz * depth_uv;  // uv shift per depth
  const int steps = static_cast<int>(Real(kParallaxMaxSteps) +
                                     (Real(kParallaxMinSteps - kParallaxMaxSteps)) * cz);
  const Real step = Real(1) / Real(steps);
  Real prev_gap = -(Real(1) - height(u, v));  // ray depth minus surface depth, < 0 above
  if (prev_gap >= Real(0)) return {u, v, Real(0)};
  for (int i = 1; i <= steps; ++i) {
    const Real d = Real(i) * step;
    const Real gap = d - (Real(1) - height(u + du * d, v + dv * d));
    if (gap >= Real(0)) {
      const Real a = prev_gap / (prev_gap - gap);
      const Real dh = d - step + a * step;
      return {u + du * dh, v + dv * dh, dh};
    }
    prev_gap = gap;
  }
  return {u + du, v + dv, Real(1)};
}

// Visibility in [0, 1] of the light along `light` (tangent frame, unit, from the surface) from
// the height-field point `at`: the light ray is marched up to the polygon, every texel above
// it occludes in proportion to how far above and how near (Tatarchuk's soft shadows).
template <class Height>
KOKKOS_INLINE_FUNCTION Real parallax_self_shadow(const Height& height, const ParallaxHit& at,
                                                 const Vec3& light, Real depth_uv) {
  if (!(light.z > Real(0)) || at.depth <= Real(0)) return Real(1);
  const Real cz = math::fmax(light.z, kParallaxMinCos);
  const Real du = light.x / cz * depth_uv, dv = light.y / cz * depth_uv;
  const int steps = static_cast<int>(Real(kParallaxMaxSteps) +
                                     (Real(kParallaxMinSteps - kParallaxMaxSteps)) * cz);
  Real blocked = Real(0);
  for (int i = 1; i < steps; ++i) {
    const Real up = at.depth * Real(i) / Real(steps);  // depth climbed along the light ray
    const Real ray_depth = at.depth - up;
    const Real surface_depth = Real(1) - height(at.u + du * up, at.v + dv * up);
    const Real above = ray_depth - surface_depth;  // > 0: the surface is above the light ray
    blocked = math::fmax(blocked, above * (Real(1) - Real(i) / Real(steps)));
  }
  return math::fmax(Real(0), Real(1) - kParallaxShadowSharpness * blocked);
}

}  // namespace rtmini::sketch
