#pragma once
// Surface points and the scattering of the seeds' Phong-style material: Lambert
// diffuse (Kd, weighted by opacity d), mirror or glossy reflection (Ks), and for
// d < 1 a dielectric interface (index Ni) with exact unpolarised Fresnel
// reflectance. Glossy directions follow a Phong lobe cos^Ns around the mirror or
// refracted direction (the distribution seed's "interval around the perfect
// reflection vector"; Cook et al. 1984).
#include "device_scene.hpp"
#include "rtmini/geometry/offset.hpp"
#include "rtmini/geometry/triangle.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini::sketch {

// Ns at or above this (or Ns <= 0) is a perfect mirror.
inline constexpr Real kMirrorShininess = Real(10000);

struct Surface {
  Vec3 p;
  Vec3 ng;  // geometric normal, on the side the ray came from
  Vec3 ns;  // shading normal, same side as ng
  int material = 0;
  int object = -1;
  bool front = true;          // the ray hit the side the winding calls outside
  Real coordinate_bound = 0;  // the scene's, for offset_ray_origin
  Real self_shadow = 1;       // height-field self-shadowing of the direct light (parallax.hpp)
  Real time = 0;              // the instant it was seen at (the ray's; shadow rays share it)
};

template <class Scene>
KOKKOS_INLINE_FUNCTION Surface surface_at(const Scene& scene, const Ray& ray, const Hit& hit,
                                          bool smooth) {
  Surface s;
  const int tri = hit.prim;
  const Triangle& t = scene.mesh.tris(tri);
  s.p = barycentric_point(t.a, t.b, t.c, hit.u, hit.v);
  s.coordinate_bound = scene.mesh.coordinate_bound;
  const Vec3 ng = triangle_normal(t.a, t.b, t.c);
  s.object = scene.mesh.tri_object(tri);
  s.material = scene.mesh.tri_material(tri);
  Vec3 ns = ng;
  const ObjectShading& o = scene.objects(s.object);
  if (o.radius > Real(0)) {
    ns = normalize(s.p - o.center);
    if (dot(ns, ng) < Real(0)) ns = -ns;
  } else if (smooth) {
    // Interpolated corner normals of the triangle's smoothing groups (split at creases).
    Vec3 acc(Real(0));
    const Real w[3] = {Real(1) - hit.u - hit.v, hit.u, hit.v};
    for (int k = 0; k < 3; ++k) acc += scene.shading_normals(scene.corner_normal(tri, k)) * w[k];
    ns = normalize(acc);
    if (!(dot(ns, ng) > Real(0))) ns = ng;
  }
  s.time = ray.time;
  s.front = dot(ray.dir, ng) < Real(0);
  s.ng = s.front ? ng : -ng;
  s.ns = s.front ? ns : -ns;
  return s;
}

KOKKOS_INLINE_FUNCTION bool is_glossy(Real shininess) {
  return shininess > Real(0) && shininess < kMirrorShininess;
}

// Direction in a Phong lobe cos^n(theta) around the unit axis.
KOKKOS_INLINE_FUNCTION Vec3 phong_lobe(const Vec3& axis, Real n, Real u1, Real u2) {
  const Real cos_t = math::pow(u1, Real(1) / (n + Real(1)));
  const Real sin_t = math::sqrt(math::fmax(Real(0), Real(1) - cos_t * cos_t));
  const Real phi = Real(2 * math::kPi) * u2;
  return Frame(axis).to_world(Vec3(sin_t * math::cos(phi), sin_t * math::sin(phi), cos_t));
}

// Solid-angle pdf of phong_lobe's direction d: (n + 1) / (2 pi) cos^n(theta), 0 behind the axis.
KOKKOS_INLINE_FUNCTION Real phong_pdf(const Vec3& axis, Real n, const Vec3& d) {
  const Real cos_t = dot(axis, d);
  if (!(cos_t > Real(0))) return Real(0);
  return (n + Real(1)) * Real(1 / (2 * math::kPi)) * math::pow(cos_t, n);
}

// Exact Fresnel reflectance for unpolarised light; eta = n_incident / n_transmitted.
KOKKOS_INLINE_FUNCTION Real fresnel_dielectric(Real cos_i, Real cos_t, Real eta) {
  const Real rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  const Real rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  return Real(0.5) * (rs * rs + rp * rp);
}

// The specular part of a material hit from direction `dir`: reflection weight (Ks plus the
// Fresnel-reflected share of the transparency) around the mirror direction, transmission
// weight around the refracted one (zero under total internal reflection).
struct SpecularLobes {
  Vec3 w_r, w_t;
  Vec3 reflected, refracted;
};

KOKKOS_INLINE_FUNCTION SpecularLobes specular_lobes(const DeviceMaterial& m, const Surface& s,
                                                    const Vec3& dir) {
  const Real transparency = Real(1) - m.opacity;
  Real fresnel = Real(0);
  SpecularLobes l;
  l.refracted = Vec3(Real(0));
  bool can_refract = false;
  if (transparency > Real(0)) {
    const Real eta = s.front ? Real(1) / m.ior : m.ior;
    const Real cos_i = math::fmin(Real(1), math::fmax(Real(0), -dot(dir, s.ns)));
    const Real sin2_t = eta * eta * (Real(1) - cos_i * cos_i);
    if (sin2_t >= Real(1)) {
      fresnel = Real(1);  // total internal reflection
    } else {
      const Real cos_t = math::sqrt(Real(1) - sin2_t);
      fresnel = fresnel_dielectric(cos_i, cos_t, eta);
      l.refracted = normalize(dir * eta + s.ns * (eta * cos_i - cos_t));
      can_refract = true;
    }
  }
  l.reflected = reflect(dir, s.ns);
  l.w_r = m.reflective + Vec3(transparency * fresnel);
  l.w_t = can_refract ? Vec3(transparency * (Real(1) - fresnel)) : Vec3(Real(0));
  return l;
}

// How a continuation ray was chosen: a perfect mirror or refraction (a delta direction no
// light sample can find), a glossy Phong lobe, or diffuse interreflection.
enum class Scatter { kSpecular, kGlossy, kDiffuse };

// One continuation ray chosen among reflection, transmission and (when `indirect`)
// diffuse interreflection, with probability proportional to each weight's largest
// component; `weight` is the weight divided by that probability. For a glossy lobe,
// `lobe_pdf` is the solid-angle pdf of the direction within its lobe (for MIS against
// light sampling). False: absorbed.
KOKKOS_INLINE_FUNCTION bool sample_continuation(const DeviceMaterial& m, const Surface& s,
                                                const Vec3& dir, bool indirect, Real u_pick,
                                                Real u1, Real u2, Ray& next, Vec3& weight,
                                                Scatter& kind, Real& lobe_pdf) {
  const SpecularLobes lobes = specular_lobes(m, s, dir);
  const Vec3 w_d = indirect ? m.diffuse * m.opacity : Vec3(Real(0));
  const Real p_r = max_component(lobes.w_r), p_t = max_component(lobes.w_t),
             p_d = max_component(w_d);
  const Real total = p_r + p_t + p_d;
  if (!(total > Real(0))) return false;
  const Real pick = u_pick * total;
  const bool glossy = is_glossy(m.shininess);
  kind = glossy ? Scatter::kGlossy : Scatter::kSpecular;
  lobe_pdf = Real(0);
  if (pick < p_r || pick < p_r + p_t) {
    const bool reflection = pick < p_r;
    const Vec3 axis = reflection ? lobes.reflected : lobes.refracted;
    const Vec3 side = reflection ? s.ng : -s.ng;
    Vec3 d = axis;
    if (glossy) {
      d = phong_lobe(axis, m.shininess, u1, u2);
      lobe_pdf = phong_pdf(axis, m.shininess, d);
    }
    if (dot(d, side) <= Real(0)) return false;
    next.org = offset_ray_origin(s.p, side, s.coordinate_bound);
    next.dir = d;
    weight = reflection ? lobes.w_r * (total / p_r) : lobes.w_t * (total / p_t);
  } else {
    const Vec3 d = Frame(s.ns).to_world(cosine_hemisphere(u1, u2));
    if (dot(d, s.ng) <= Real(0)) return false;
    next.org = offset_ray_origin(s.p, s.ng, s.coordinate_bound);
    next.dir = d;
    weight = w_d * (total / p_d);
    kind = Scatter::kDiffuse;
  }
  next.tmin = Real(0);
  next.tmax = Real(1e30);
  return true;
}

}  // namespace rtmini::sketch
