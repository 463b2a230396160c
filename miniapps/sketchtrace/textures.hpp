#pragma once
// Image maps on the device: every distinct image once, with its box-filtered mip
// chain, in one texel View (3 floats per texel; colour maps linear, data maps as
// stored), looked up trilinearly at a level of detail chosen by ray cones
// (Akenine-Moller et al., Ray Tracing Gems ch. 20): the cone's width at the hit,
// the triangle's texel density and the incidence angle give log2 of the footprint
// in texels, so distant and grazing surfaces read coarser levels and do not alias.
#include "rtmini/geometry/vec.hpp"
#include "rtmini/kokkos_compat.hpp"

namespace rtmini::sketch {

// One mip level: `width` x `height` texels from texel `offset` of the texel View.
struct TextureLevel {
  int offset = 0, width = 1, height = 1;
};

// An image: levels [first_level, first_level + levels) of the level table, finest first.
struct TextureDesc {
  int first_level = 0, levels = 1;
};

// The maps of one material (texture ids, -1 = none) and their height scales (mesh units of a
// white texel, MTL -bm).
struct MaterialMapIds {
  int diffuse = -1, specular = -1, normal = -1, bump = -1, displacement = -1;
  Real bump_scale = 1, displacement_scale = 0;
  KOKKOS_INLINE_FUNCTION bool perturbs_normal() const {
    return normal >= 0 || bump >= 0 || displacement >= 0;
  }
};

// A triangle's texture coordinates and tangent frame corners (tangent_frame.hpp), plus what
// the ray-cone LOD needs: lod_base = 0.5 log2(uv area / world area), and world_per_uv, the
// world length of one unit of u or v (sqrt of the inverse ratio) for height-field slopes.
struct TexturedTriangle {
  Real u[3] = {0, 0, 0}, v[3] = {0, 0, 0};
  Vec3 tangent[3];
  Real sign = 1;  // bitangent = sign * cross(normal, tangent)
  Real lod_base = 0;
  Real world_per_uv = 1;
  bool has_uv = false;
};

template <class MemSpace>
struct SurfaceMaps {
  Kokkos::View<float*, MemSpace> texels;  // 3 floats per texel
  Kokkos::View<TextureLevel*, MemSpace> levels;
  Kokkos::View<TextureDesc*, MemSpace> textures;
  Kokkos::View<MaterialMapIds*, MemSpace> materials;  // per scene material
  Kokkos::View<TexturedTriangle*, MemSpace> tris;     // per triangle, original order
  std::size_t bytes = 0;                              // device bytes of the Views above
  bool any = false;                                   // some material has a map
};

// A ray cone (RTG ch. 20): `width` at the current hit, growing by `spread` (radians, small-angle)
// per unit of distance. The camera's cone spreads by one pixel's angle; a scattering event
// widens the spread by the lobe's angular size (glossy: the Phong lobe's ~1/sqrt(Ns + 1),
// diffuse: one radian, where every texture is blurred anyway). Mirrors and refractions keep
// it: surfaces are taken as locally flat (the paper's curvature term is left out).
struct RayCone {
  Real width = 0, spread = 0;
  KOKKOS_INLINE_FUNCTION void advance(Real t) { width += spread * t; }
  KOKKOS_INLINE_FUNCTION void scatter(Real shininess, bool glossy, bool diffuse) {
    if (diffuse)
      spread += Real(1);
    else if (glossy)
      spread += Real(1) / math::sqrt(shininess + Real(1));
  }
};

// Level of detail (fractional mip level) for a cone of `width` hitting a triangle of
// `lod_base` at |cos| `cos_incidence`, on a `width` x `height` image: 0.5 log2(texels per
// world area) + 0.5 log2(footprint area), the footprint being the cone's ellipse, width x
// width / |cos| (RTG ch. 20 eq. 34 takes the major axis, log2(width / |cos|), which blurs
// grazing surfaces along their minor axis too: results/accuracy/texture_filter.md).
KOKKOS_INLINE_FUNCTION Real texture_lod(Real lod_base, int tex_width, int tex_height,
                                        Real cone_width, Real cos_incidence) {
  const Real c = math::fmax(math::fabs(cos_incidence), Real(1e-4));
  const Real w = math::fmax(cone_width, Real(1e-20));
  return lod_base + Real(0.5) * math::log2(Real(tex_width) * Real(tex_height)) + math::log2(w) -
         Real(0.5) * math::log2(c);
}

// Texel (x, y) of one level, wrapped (OBJ maps repeat outside [0, 1]).
template <class Maps>
KOKKOS_INLINE_FUNCTION Vec3 texel_at(const Maps& maps, const TextureLevel& l, int x, int y) {
  x %= l.width;
  y %= l.height;
  if (x < 0) x += l.width;
  if (y < 0) y += l.height;
  const int i = 3 * (l.offset + y * l.width + x);
  return Vec3(Real(maps.texels(i)), Real(maps.texels(i + 1)), Real(maps.texels(i + 2)));
}

// Bilinear lookup at (u, v) of one level; v grows upwards, image rows downwards.
template <class Maps>
KOKKOS_INLINE_FUNCTION Vec3 bilinear(const Maps& maps, const TextureLevel& l, Real u, Real v) {
  const Real x = u * Real(l.width) - Real(0.5);
  const Real y = (Real(1) - v) * Real(l.height) - Real(0.5);
  const Real fx = math::floor(x), fy = math::floor(y);
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const Real ax = x - fx, ay = y - fy;
  const Vec3 top = texel_at(maps, l, x0, y0) * (Real(1) - ax) + texel_at(maps, l, x0 + 1, y0) * ax;
  const Vec3 bottom =
      texel_at(maps, l, x0, y0 + 1) * (Real(1) - ax) + texel_at(maps, l, x0 + 1, y0 + 1) * ax;
  return top * (Real(1) - ay) + bottom * ay;
}

// Trilinear lookup: the two levels around `lod`, clamped to the chain.
template <class Maps>
KOKKOS_INLINE_FUNCTION Vec3 sample_texture(const Maps& maps, int texture, Real u, Real v,
                                           Real lod) {
  const TextureDesc d = maps.textures(texture);
  const Real top = Real(d.levels - 1);
  const Real l = math::fmin(math::fmax(lod, Real(0)), top);
  const int l0 = static_cast<int>(math::floor(l));
  const int l1 = l0 + 1 < d.levels ? l0 + 1 : l0;
  const Real a = l - Real(l0);
  const Vec3 c0 = bilinear(maps, maps.levels(d.first_level + l0), u, v);
  if (l1 == l0 || a <= Real(0)) return c0;
  return c0 * (Real(1) - a) + bilinear(maps, maps.levels(d.first_level + l1), u, v) * a;
}

// The LOD of `texture` for a cone on triangle record `t`.
template <class Maps>
KOKKOS_INLINE_FUNCTION Real lod_of(const Maps& maps, int texture, const TexturedTriangle& t,
                                   Real cone_width, Real cos_incidence) {
  const TextureLevel& finest = maps.levels(maps.textures(texture).first_level);
  return texture_lod(t.lod_base, finest.width, finest.height, cone_width, cos_incidence);
}

}  // namespace rtmini::sketch
