#pragma once
// Feature lines from a ray stencil (Choudhury & Parker, "Ray tracing NPR-style
// feature lines", NPAR 2009; hand-drawn seed §5): a centre ray plus 8 rays on a
// ring of radius h pixels. A ring ray marks the centre when it sees another object
// (silhouette), a normal turned by more than the crease angle (crease) or a relative
// depth jump (self-occluding silhouette). The seed's anti-aliased edges doubled
// because both sides of a boundary marked themselves; here only the side whose
// centre hit is nearer (lower object id at equal depth) marks it, so a line is
// about h pixels wide. The stencil runs at several jittered sub-pixel centres and
// the fractions are averaged, which anti-aliases the line.
#include "light_sampling.hpp"
#include "rtmini/scene/camera.hpp"

namespace rtmini::sketch {

struct StencilParams {
  Real radius = Real(1.5);  // h, pixels
  Real cos_crease = Real(0.5);
  Real depth_threshold = Real(0.1);
  int samples = 4;
  bool edges = true;
  bool smooth = true;
};

struct StencilHit {
  int object = -1;
  Real depth = Real(1e30);
  Vec3 normal;
};

template <class Scene>
KOKKOS_INLINE_FUNCTION StencilHit stencil_hit(const Scene& scene, const DeviceCamera& cam, Real px,
                                              Real py, const StencilParams& sp, TraceCounter& c) {
  const Ray ray = cam.generate(px, py, Real(0.5), Real(0.5), Real(0), false, false);
  const Hit h = scene_closest(scene, ray, c);
  StencilHit out;
  if (!h.valid()) return out;
  const Surface s = scene_surface(scene, ray, h, sp.smooth);
  out.object = s.object;
  out.depth = h.t;
  out.normal = s.ns;
  return out;
}

// Fraction in [0, 1] of ring rays that mark the centre as an edge (max over the three criteria).
template <class Scene>
KOKKOS_INLINE_FUNCTION Real stencil_fraction(const Scene& scene, const DeviceCamera& cam, Real cx,
                                             Real cy, const StencilParams& sp, TraceCounter& c) {
  const StencilHit centre = stencil_hit(scene, cam, cx, cy, sp, c);
  int silhouette = 0, crease = 0, depth = 0;
  for (int k = 0; k < 8; ++k) {
    const Real angle = Real(math::kPi / 4) * Real(k);
    const StencilHit ring = stencil_hit(scene, cam, cx + sp.radius * math::cos(angle),
                                        cy + sp.radius * math::sin(angle), sp, c);
    const bool owner =
        centre.depth < ring.depth || (centre.depth == ring.depth && centre.object < ring.object);
    if (!owner || centre.object < 0) continue;
    if (ring.object != centre.object) {
      ++silhouette;
    } else {
      if (dot(centre.normal, ring.normal) < sp.cos_crease) ++crease;
      if (ring.depth - centre.depth > sp.depth_threshold * centre.depth) ++depth;
    }
  }
  const int worst = silhouette > crease ? (silhouette > depth ? silhouette : depth)
                                        : (crease > depth ? crease : depth);
  return Real(worst) / Real(8);
}

}  // namespace rtmini::sketch
