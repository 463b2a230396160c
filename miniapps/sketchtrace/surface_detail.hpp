#pragma once
// Surface detail at a hit of a textured material: parallax occlusion (disp), then
// the colour maps (map_Kd, map_Ks multiply Kd, Ks) and the shading normal from a
// tangent-space normal map (norm), or else from the slope of a bump map (map_bump)
// or of the height field. Called by the kernel only when the scene has maps
// (FeatureBits kTextures), so scenes without maps run exactly the old code.
#include "parallax.hpp"
#include "shading.hpp"
#include "tangent_frame.hpp"
#include "textures.hpp"

namespace rtmini::sketch {

// h(u, v) of one height texture at a fixed LOD (the red channel).
template <class Maps>
struct HeightLookup {
  const Maps& maps;
  int texture;
  Real lod;
  KOKKOS_INLINE_FUNCTION Real operator()(Real u, Real v) const {
    return sample_texture(maps, texture, u, v, lod).x;
  }
};

// The normal of the surface p + scale h(u, v) n: n - scale grad h, with grad h along t and b
// by central differences one texel of the LOD apart, per world length (world_per_uv).
template <class Maps>
KOKKOS_INLINE_FUNCTION Vec3 height_slope_normal(const Maps& maps, int texture, Real u, Real v,
                                                Real lod, const TangentFrame& f, Real scale,
                                                Real world_per_uv) {
  const TextureLevel finest = maps.levels(maps.textures(texture).first_level);
  const Real texel = math::pow(Real(2), math::fmax(lod, Real(0)));
  const Real du = texel / Real(finest.width), dv = texel / Real(finest.height);
  const HeightLookup<Maps> h{maps, texture, lod};
  const Real dh_du = (h(u + du, v) - h(u - du, v)) / (Real(2) * du);
  const Real dh_dv = (h(u, v + dv) - h(u, v - dv)) / (Real(2) * dv);
  const Real k = scale / world_per_uv;
  return normalize(f.n - f.t * (k * dh_du) - f.b * (k * dh_dv));
}

// Direction (world) from p towards the first quad or point light, for the height field's
// self-shadowing; zero when the scene has neither.
template <class Scene>
KOKKOS_INLINE_FUNCTION Vec3 key_light_direction(const Scene& scene, const Vec3& p) {
  if (scene.num_quads > 0) {
    const auto& q = scene.quads(0);
    return normalize(q.corner + q.u * Real(0.5) + q.v * Real(0.5) - p);
  }
  if (scene.num_points > 0) return normalize(scene.points(0).position - p);
  return Vec3(Real(0));
}

// Applies the material's maps at the hit to the surface (uv shift, shading normal, self
// shadow) and to the material (Kd, Ks); `cone` is the ray cone at the hit.
template <class Scene>
KOKKOS_INLINE_FUNCTION void apply_surface_maps(const Scene& scene, const Ray& ray, const Hit& hit,
                                               const RayCone& cone, Surface& s, DeviceMaterial& m) {
  const auto& maps = scene.maps;
  const MaterialMapIds ids = maps.materials(s.material);
  const TexturedTriangle& tri = maps.tris(hit.prim);
  if (!tri.has_uv) return;
  const Real w[3] = {Real(1) - hit.u - hit.v, hit.u, hit.v};
  Real u = 0, v = 0;
  Vec3 tangent(Real(0));
  for (int k = 0; k < 3; ++k) {
    u += tri.u[k] * w[k];
    v += tri.v[k] * w[k];
    tangent += tri.tangent[k] * w[k];
  }
  const Real cos_i = dot(ray.dir, s.ng);
  // The frame of the side the winding calls outside: maps are painted on that side.
  const Vec3 n_out = s.front ? s.ns : -s.ns;
  const TangentFrame frame = tangent_frame_at(n_out, tangent, tri.sign);
  Real height_lod = 0;
  if (ids.displacement >= 0 && s.front) {
    height_lod = lod_of(maps, ids.displacement, tri, cone.width, cos_i);
    const HeightLookup<SurfaceMaps<MemSpace>> h{maps, ids.displacement, height_lod};
    const Real depth_uv = ids.displacement_scale / tri.world_per_uv;
    const ParallaxHit ph = parallax_occlusion(h, u, v, frame.to_local(-ray.dir), depth_uv);
    u = ph.u;
    v = ph.v;
    const Vec3 l = key_light_direction(scene, s.p);
    if (dot(l, l) > Real(0))
      s.self_shadow = parallax_self_shadow(h, ph, frame.to_local(l), depth_uv);
  }
  if (ids.diffuse >= 0)
    m.diffuse = m.diffuse * sample_texture(maps, ids.diffuse, u, v,
                                           lod_of(maps, ids.diffuse, tri, cone.width, cos_i));
  if (ids.specular >= 0)
    m.reflective =
        m.reflective * sample_texture(maps, ids.specular, u, v,
                                      lod_of(maps, ids.specular, tri, cone.width, cos_i));
  if (!ids.perturbs_normal()) return;
  Vec3 n = n_out;
  if (ids.normal >= 0) {
    const Vec3 c =
        sample_texture(maps, ids.normal, u, v, lod_of(maps, ids.normal, tri, cone.width, cos_i));
    n = normalize(frame.to_world(c * Real(2) - Vec3(Real(1))));
  } else if (ids.bump >= 0) {
    n = height_slope_normal(maps, ids.bump, u, v, lod_of(maps, ids.bump, tri, cone.width, cos_i),
                            frame, ids.bump_scale, tri.world_per_uv);
  } else if (ids.displacement >= 0) {
    n = height_slope_normal(maps, ids.displacement, u, v, height_lod, frame, ids.displacement_scale,
                            tri.world_per_uv);
  }
  // A perturbed normal must stay on the geometric normal's side (light and continuation
  // tests use both); past it, the interpolated normal is kept.
  const Vec3 ng_out = s.front ? s.ng : -s.ng;
  if (dot(n, ng_out) > Real(0)) s.ns = s.front ? n : -n;
}

}  // namespace rtmini::sketch
