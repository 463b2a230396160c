// Image maps (issue 24): mip chains keep the mean of what they cover; the ray-cone LOD picks
// the level whose texel matches the cone's footprint; tangent frames keep their handedness for
// mirrored texture coordinates; parallax occlusion finds an analytic step; the OBJ/MTL reader
// fills texcoords and maps and names the MTL line of a missing image.
#include "surface_maps.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "../optional_features.hpp"
#include "displace.hpp"
#include "parallax.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "tangent_frame.hpp"

namespace rtmini::sketch {
namespace {

Image ramp(int w, int h) {
  Image img(w, h, 1);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img.at(x, y, 0) = static_cast<float>(x + 10 * y);
  return img;
}

double mean(const Image& img) {
  double s = 0;
  for (float v : img.data) s += v;
  return s / img.data.size();
}

TEST(MipChain, EachLevelAveragesTheBlockItCovers) {
  const Image level0 = ramp(4, 2);
  const Image level1 = downsample(level0);
  ASSERT_EQ(level1.width, 2);
  ASSERT_EQ(level1.height, 1);
  EXPECT_FLOAT_EQ(level1.at(0, 0, 0), (0 + 1 + 10 + 11) / 4.f);
  EXPECT_FLOAT_EQ(level1.at(1, 0, 0), (2 + 3 + 12 + 13) / 4.f);
  // Odd sizes: 5 x 3 -> 2 x 1, the second texel takes columns 2-4 and all 3 rows.
  const Image odd = downsample(ramp(5, 3));
  ASSERT_EQ(odd.width, 2);
  ASSERT_EQ(odd.height, 1);
  EXPECT_FLOAT_EQ(odd.at(1, 0, 0), (2 + 3 + 4) / 3.f + 10.f);
}

TEST(MipChain, PackedChainRunsDownToOneTexelHoldingTheMean) {
  PackedTextures packed;
  const Image img = ramp(8, 4);
  const int id = packed.add(img);
  ASSERT_EQ(id, 0);
  const TextureDesc d = packed.textures[0];
  ASSERT_EQ(d.levels, 4);  // 8x4, 4x2, 2x1, 1x1
  const TextureLevel last = packed.levels[d.first_level + d.levels - 1];
  EXPECT_EQ(last.width, 1);
  EXPECT_EQ(last.height, 1);
  EXPECT_NEAR(packed.texels[3 * last.offset], mean(img), 1e-4);
  EXPECT_EQ(packed.texels.size(), 3u * (32 + 8 + 2 + 1));
}

// A unit square in the xy plane mapped to [0, 1]^2, as two triangles.
struct UnitQuad {
  std::vector<Vec3d> positions{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  std::vector<std::array<int, 3>> tris{{0, 1, 2}, {0, 2, 3}};
  std::vector<std::array<int, 3>> uv_ids{{0, 1, 2}, {0, 2, 3}};
  std::vector<TexCoord> texcoords{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  std::vector<std::array<int, 3>> normal_ids{{0, 0, 0}, {0, 0, 0}};
  std::vector<Vec3> normals{Vec3(Real(0), Real(0), Real(1))};
  std::vector<TexturedTriangle> records() const {
    return textured_triangles(positions, tris, uv_ids, texcoords, normal_ids, normals);
  }
};

TEST(RayConeLod, ConeOfOneTexelReadsLevelZeroAndEachDoublingOneLevelUp) {
  const UnitQuad q;
  const auto r = q.records();
  ASSERT_TRUE(r[0].has_uv);
  EXPECT_NEAR(r[0].lod_base, 0.0, 1e-6);  // uv area = world area
  EXPECT_NEAR(r[0].world_per_uv, 1.0, 1e-6);
  const int size = 256;
  const Real texel = Real(1) / size;  // world size of a texel on this quad
  EXPECT_NEAR(texture_lod(r[0].lod_base, size, size, texel, Real(1)), 0.0, 1e-4);
  EXPECT_NEAR(texture_lod(r[0].lod_base, size, size, 4 * texel, Real(1)), 2.0, 1e-4);
  // Grazing at 75.5 degrees the footprint stretches by 1 / cos = 4 along one axis: its area
  // matches 2 x 2 texels, one level coarser.
  EXPECT_NEAR(texture_lod(r[0].lod_base, size, size, texel, Real(0.25)), 1.0, 1e-4);
  // The same texture tiled 8 times over the quad: texels 8 times smaller, 3 levels finer.
  UnitQuad tiled;
  for (TexCoord& t : tiled.texcoords) t = {t.u * 8, t.v * 8};
  EXPECT_NEAR(texture_lod(tiled.records()[0].lod_base, size, size, texel, Real(1)), 3.0, 1e-4);
}

TEST(RayConeLod, TrilinearLookupBlendsTheTwoLevelsAroundTheLod) {
  // A 2 x 2 black/white checker: level 0 returns texels at their centres, level 1 the mean.
  Image img(2, 2, 1);
  img.at(0, 0, 0) = 1.f;
  img.at(1, 1, 0) = 1.f;
  PackedTextures packed;
  packed.add(img);
  SurfaceMaps<Kokkos::HostSpace> maps;
  maps.texels = Kokkos::View<float*, Kokkos::HostSpace>("texels", packed.texels.size());
  for (std::size_t i = 0; i < packed.texels.size(); ++i) maps.texels(i) = packed.texels[i];
  maps.levels = Kokkos::View<TextureLevel*, Kokkos::HostSpace>("levels", packed.levels.size());
  for (std::size_t i = 0; i < packed.levels.size(); ++i) maps.levels(i) = packed.levels[i];
  maps.textures = Kokkos::View<TextureDesc*, Kokkos::HostSpace>("textures", 1);
  maps.textures(0) = packed.textures[0];
  // Texel (0, 0) is the top-left one: u = 0.25, v = 0.75.
  EXPECT_NEAR(sample_texture(maps, 0, Real(0.25), Real(0.75), Real(0)).x, 1.0, 1e-6);
  EXPECT_NEAR(sample_texture(maps, 0, Real(0.75), Real(0.75), Real(0)).x, 0.0, 1e-6);
  EXPECT_NEAR(sample_texture(maps, 0, Real(0.25), Real(0.75), Real(1)).x, 0.5, 1e-6);
  EXPECT_NEAR(sample_texture(maps, 0, Real(0.25), Real(0.75), Real(0.5)).x, 0.75, 1e-6);
  EXPECT_NEAR(sample_texture(maps, 0, Real(0.25), Real(0.75), Real(9)).x, 0.5, 1e-6);  // clamped
}

TEST(TangentFrame, HandednessFollowsMirroredTextureCoordinates) {
  const UnitQuad q;
  const CornerTangents plain =
      corner_tangents(q.positions, q.tris, q.uv_ids, q.texcoords, q.normal_ids, q.normals);
  EXPECT_EQ(plain.sign[0], 1.f);
  EXPECT_NEAR(plain.tangent[0][0].x, 1.0, 1e-6);
  // u mirrored (runs along -x): the tangent turns round, the sign flips, and the bitangent
  // sign * cross(n, t) still runs along +v (+y).
  UnitQuad mirrored;
  for (TexCoord& t : mirrored.texcoords) t.u = 1 - t.u;
  const CornerTangents m =
      corner_tangents(mirrored.positions, mirrored.tris, mirrored.uv_ids, mirrored.texcoords,
                      mirrored.normal_ids, mirrored.normals);
  for (int t = 0; t < 2; ++t) {
    EXPECT_EQ(m.sign[t], -1.f);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.tangent[t][k].x, -1.0, 1e-6);
  }
  const Vec3 n(Real(0), Real(0), Real(1));
  const TangentFrame f0 = tangent_frame_at(n, plain.tangent[0][0], Real(plain.sign[0]));
  const TangentFrame f1 = tangent_frame_at(n, m.tangent[0][0], Real(m.sign[0]));
  EXPECT_NEAR(f0.b.y, 1.0, 1e-6);
  EXPECT_NEAR(f1.b.y, 1.0, 1e-6);
  // Gram-Schmidt: a tangent leaning into the normal comes back orthogonal and unit.
  const TangentFrame g = tangent_frame_at(n, Vec3(Real(1), Real(0), Real(3)), Real(1));
  EXPECT_NEAR(dot(g.t, n), 0.0, 1e-6);
  EXPECT_NEAR(length(g.t), 1.0, 1e-6);
}

// A step: h = 1 (the polygon itself) for u < 0.5, h = 0 (a pit of full depth) beyond.
struct StepHeight {
  KOKKOS_INLINE_FUNCTION Real operator()(Real u, Real) const {
    return u < Real(0.5) ? Real(1) : Real(0);
  }
};

TEST(Parallax, FindsThePitFloorAndTheStepWallAnalytically) {
  const StepHeight h;
  const Real depth_uv = Real(0.1);
  // Looking along +u at 45 degrees down into the pit: the floor is met depth_uv further on.
  const Real s = Real(std::sqrt(0.5));
  const Vec3 towards_minus_u_eye(-s, Real(0), s);  // the eye is at -u: the ray runs to +u
  const ParallaxHit floor =
      parallax_occlusion(h, Real(0.6), Real(0.5), towards_minus_u_eye, depth_uv);
  EXPECT_NEAR(floor.depth, 1.0, 1e-5);
  EXPECT_NEAR(floor.u, 0.7, 1e-5);
  // Looking along -u from u = 0.55: the wall at u = 0.5 is met at depth 0.05 / 0.1 = 0.5, to
  // within one march step (1/steps of the depth; the chord refinement cannot see a vertical
  // wall's position inside the step).
  const Vec3 towards_plus_u_eye(s, Real(0), s);
  const ParallaxHit wall =
      parallax_occlusion(h, Real(0.55), Real(0.5), towards_plus_u_eye, depth_uv);
  const int steps =
      static_cast<int>(kParallaxMaxSteps + (kParallaxMinSteps - kParallaxMaxSteps) * s);
  EXPECT_NEAR(wall.depth, 0.5, 1.0 / steps);
  EXPECT_NEAR(wall.u, 0.5, depth_uv / steps);
  // On the plateau nothing shifts.
  const ParallaxHit top = parallax_occlusion(h, Real(0.3), Real(0.5), towards_plus_u_eye, depth_uv);
  EXPECT_EQ(top.depth, Real(0));
  EXPECT_EQ(top.u, Real(0.3));
  // Self-shadowing: the pit floor near the wall is dark for a light beyond the wall (at -u),
  // lit for a light straight above.
  const ParallaxHit near_wall{Real(0.52), Real(0.5), Real(1)};
  const Vec3 towards_minus_u_light(-s, Real(0), s);
  EXPECT_LT(parallax_self_shadow(h, near_wall, towards_minus_u_light, depth_uv), 0.5);
  EXPECT_EQ(parallax_self_shadow(h, near_wall, Vec3(s, Real(0), s), depth_uv),
            Real(1));  // a light at +u, away from the wall
  EXPECT_EQ(parallax_self_shadow(h, near_wall, Vec3(Real(0), Real(0), Real(1)), depth_uv), Real(1));
}

TEST(Displacement, TessellatedGridKeepsItsBorderAndSinksTheInteriorByTheHeight) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  Face f;
  f.count = 4;
  f.v = {0, 1, 2, 3};
  f.uv = {0, 1, 2, 3};
  f.material = 0;
  mesh.faces.push_back(f);
  Material m;
  m.maps.displacement = "height.png";
  m.maps.displacement_scale = 0.2f;
  mesh.materials.push_back(m);
  Image height(4, 4, 3);
  for (float& v : height.data) v = 0.25f;  // depth 0.75 x 0.2 below the polygon
  const std::vector<MapImage> images{{"height.png", false, height}};

  Mesh off = mesh;
  EXPECT_EQ(apply_displacement_mode(off, images, DisplacementMode::kOff, 3), 1u);
  ASSERT_EQ(off.faces.size(), 1u);
  EXPECT_TRUE(off.materials[off.faces[0].material].maps.displacement.empty());

  EXPECT_EQ(apply_displacement_mode(mesh, images, DisplacementMode::kTessellate, 2), 1u);
  EXPECT_EQ(mesh.faces.size(), 2u * 4 * 4);
  EXPECT_TRUE(mesh.materials[mesh.faces[0].material].maps.displacement.empty());
  int border = 0, inside = 0;
  for (std::size_t i = 4; i < mesh.positions.size(); ++i) {
    const Vec3d& p = mesh.positions[i];
    const bool on_border = p.x == 0 || p.y == 0 || p.x == 1 || p.y == 1;
    EXPECT_NEAR(p.z, on_border ? 0.0 : -0.75 * 0.2, 1e-6) << p.x << " " << p.y;
    (on_border ? border : inside) += 1;
  }
  EXPECT_EQ(border, 16);
  EXPECT_EQ(inside, 9);
}

void write_text(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

TEST(ObjMaps, TexcoordsAndMapsAreReadAndAMissingImageNamesItsMtlLine) {
  RTMINI_REQUIRE_PNG();
  const std::string dir = ::testing::TempDir();
  Image img(2, 2);
  write_png(dir + "maps_test_kd.png", img);
  write_text(dir + "maps_test.mtl",
             "newmtl a\nKd 1 1 1\nmap_Kd maps_test_kd.png\nmap_bump -bm 0.25 maps_test_kd.png\n");
  write_text(dir + "maps_test.obj",
             "mtllib maps_test.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
             "usemtl a\nf 1/1 2/2 3/3\n");
  const Mesh m = read_obj(dir + "maps_test.obj");
  ASSERT_EQ(m.texcoords.size(), 3u);
  EXPECT_EQ(m.faces[0].uv[1], 1);
  EXPECT_FLOAT_EQ(m.texcoords[1].u, 1.f);
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0].maps.diffuse, dir + "maps_test_kd.png");
  EXPECT_EQ(m.materials[0].maps.bump, dir + "maps_test_kd.png");
  EXPECT_FLOAT_EQ(m.materials[0].maps.bump_scale, 0.25f);

  write_text(dir + "maps_test.mtl", "newmtl a\nKd 1 1 1\n\nnorm -bm 2 no_such_map.png\n");
  try {
    read_obj(dir + "maps_test.obj");
    FAIL() << "a missing image map was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("maps_test.mtl:4:"), std::string::npos) << what;
    EXPECT_NE(what.find("no_such_map.png"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rtmini::sketch
