// `bake render` against closed forms: a map of one colour renders that colour on covered
// pixels and the background elsewhere; a view-dependent map renders, at each pixel, the
// baker's lookup of the camera-ray direction (camera -> surface) among the Fibonacci viewpoints.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "render_map.hpp"
#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/bakeshop_binary.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/sampling/fibonacci_lookup.hpp"

namespace rtmini::bake {
namespace {

constexpr int kSize = 64;

// The square [-1,1]^2 at z = 0 facing +z (one quad, two triangles), N viewpoints per vertex
// coloured by colour_of(direction).
template <class ColourFn>
Mesh square_map(int n, ColourFn colour_of) {
  Mesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  Material mat;
  m.materials.push_back(mat);
  Face f;
  f.count = 4;
  f.v = {0, 1, 2, 3};
  f.material = 0;
  m.faces.push_back(f);
  m.objects.push_back("square");
  m.viewpoints.offsets.push_back(0);
  for (int v = 0; v < 4; ++v) {
    for (int j = 0; j < n; ++j) {
      const Vec3f d(fibonacci_point(j, n));
      m.viewpoints.dirs.push_back(d);
      m.viewpoints.colors.push_back(colour_of(d));
    }
    m.viewpoints.offsets.push_back(m.viewpoints.dirs.size());
  }
  return m;
}

DeviceCamera camera_at(const Vec3d& pos) {
  CameraDesc c;
  c.position = pos;
  c.look_at = {0, 0, 0};
  c.up = {0, 1, 0};
  c.fov_deg = 45;
  return make_camera(c, kSize, kSize);
}

// Where the pixel-centre ray of (x, y) meets the plane z = 0, and its direction.
bool plane_hit(const DeviceCamera& cam, int x, int y, Vec3& dir, Vec3& p) {
  const Ray r = cam.generate(Real(x) + Real(0.5), Real(y) + Real(0.5), Real(0.5), Real(0.5),
                             Real(0.5), false, false);
  dir = r.dir;
  if (!(r.dir.z < Real(0))) return false;
  p = r.org + r.dir * (-r.org.z / r.dir.z);
  return true;
}

// Inside the square, away from its edges (the watertight test decides exact edge pixels).
bool inside(const Vec3& p, Real margin) {
  return math::fabs(p.x) < Real(1) - margin && math::fabs(p.y) < Real(1) - margin;
}
bool outside(const Vec3& p, Real margin) {
  return math::fabs(p.x) > Real(1) + margin || math::fabs(p.y) > Real(1) + margin;
}

void check_uniform(const BakedMapHost& host, const Vec3f& c, const Vec3f& bg) {
  const BakedMapDevice dev = upload_baked_map(host, bvh::BuildQuality::kSah);
  RenderParams p;
  p.width = p.height = kSize;
  p.background = bg;
  const DeviceCamera cam = camera_at({0.3, -0.2, 3.0});
  const RenderResult r = render_baked_map(dev, cam, p);
  int covered = 0, missed = 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      Vec3 d, q;
      const bool on_plane = plane_hit(cam, x, y, d, q);
      const float* px = &r.image.data[3 * (static_cast<std::size_t>(y) * kSize + x)];
      if (on_plane && inside(q, Real(1e-3))) {
        ++covered;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(px[k], c[k], 1e-6f * c[k]) << x << "," << y;
      } else if (!on_plane || outside(q, Real(1e-3))) {
        ++missed;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(px[k], bg[k]) << x << "," << y;
      }
    }
  EXPECT_GT(covered, kSize * kSize / 4);
  EXPECT_GT(missed, kSize * kSize / 10);
}

TEST(BakeRender, UniformMapRendersItsColour) {
  const Vec3f c(0.25f, 0.6f, 1.7f), bg(0.1f, 0.2f, 0.3f);
  // As read from a file: N equal colours become one (the baker's view-independent layout).
  const BakedMapHost host =
      make_baked_map(square_map(50, [&](const Vec3f&) { return c; }), "square.bs", true);
  ASSERT_EQ(host.colors.size(), 4u);
  EXPECT_EQ(host.view_dependent_vertices, 0);
  check_uniform(host, c, bg);
  // Kept at N colours per vertex: the lookup's normalised weights must still give c.
  BakedMapHost full = host;
  full.colors.assign(4 * 50, c);
  for (int v = 0; v <= 4; ++v) full.color_offset[v] = 50 * v;
  check_uniform(full, c, bg);
}

// Colour = direction mapped to [0,1]^3: the rendered colour tells which direction was looked up.
Vec3f direction_colour(const Vec3f& d) {
  return {0.5f + 0.5f * d.x, 0.5f + 0.5f * d.y, 0.5f + 0.5f * d.z};
}

TEST(BakeRender, ViewDependentMapShowsTheCameraRayDirection) {
  const int n = 1000;
  const BakedMapHost host = make_baked_map(square_map(n, direction_colour), "square.bs", true);
  ASSERT_EQ(host.view_dependent_vertices, 4);
  const BakedMapDevice dev = upload_baked_map(host, bvh::BuildQuality::kSah);
  const auto points = fibonacci_points<Kokkos::HostSpace>(n);
  const Real radius = fibonacci_radius(n);
  Vec3f centre_colour[2];
  int cam_index = 0;
  for (const Vec3d& pos : {Vec3d(0.0, 0.0, 3.0), Vec3d(2.2, 0.4, 1.6)}) {
    const DeviceCamera cam = camera_at(pos);
    for (const Lookup lookup : {Lookup::kGrid, Lookup::kKdTree, Lookup::kSphericalFibonacci}) {
      RenderParams p;
      p.width = p.height = kSize;
      p.lookup = lookup;
      const RenderResult r = render_baked_map(dev, cam, p);
      int checked = 0;
      for (int y = 0; y < kSize; y += 3)
        for (int x = 0; x < kSize; x += 3) {
          Vec3 d, q;
          if (!plane_hit(cam, x, y, d, q) || !inside(q, Real(1e-3))) continue;
          ++checked;
          // Exact expectation: the baker's neighbour weights at d (brute force on the host).
          const ViewNeighbors nb = brute_force_neighbors(points, d, radius);
          Vec3 want(Real(0));
          for (int j = 0; j < nb.count; ++j)
            want += Vec3(direction_colour(Vec3f(points(nb.index[j])))) * nb.weight[j];
          const float* px = &r.image.data[3 * (static_cast<std::size_t>(y) * kSize + x)];
          for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(px[k], want[k], 2e-5) << "pixel " << x << "," << y;
            // The smooth closed form: a weighted mean over a cap of chord radius r about d.
            EXPECT_NEAR(px[k], 0.5f + 0.5f * d[k], 0.5 * radius * radius)
                << "pixel " << x << "," << y;
          }
          if (x == 33 && y == 33) centre_colour[cam_index] = Vec3f(px[0], px[1], px[2]);
        }
      EXPECT_GT(checked, 50);
    }
    ++cam_index;
  }
  // The looked-up direction is camera -> surface: head-on it runs along -z (blue ~ 0); from
  // the camera at +x it runs towards -x (less red than head-on).
  EXPECT_LT(centre_colour[0].z, 0.05f);
  EXPECT_LT(centre_colour[1].x - centre_colour[0].x, -0.25f);
}

// The text and binary forms of a map are read into the same colours and render identically.
TEST(BakeRender, TextAndBinaryMapsRenderAlike) {
  const Mesh mesh = square_map(200, direction_colour);
  const std::string text = ::testing::TempDir() + "render_square.bs";
  const std::string binary = ::testing::TempDir() + "render_square.bsb";
  write_bakeshop(text, mesh);
  write_bakeshop_binary(binary, mesh);
  const BakedMapHost a = read_baked_map(text), b = read_baked_map(binary);
  EXPECT_EQ(a.colors.size(), b.colors.size());
  EXPECT_EQ(a.viewpoints, 200);
  RenderParams p;
  p.width = p.height = 32;
  p.spp = 4;
  const DeviceCamera cam = camera_at({1.0, 0.5, 2.5});
  const RenderResult ra = render_baked_map(upload_baked_map(a, bvh::BuildQuality::kSah), cam, p);
  const RenderResult rb = render_baked_map(upload_baked_map(b, bvh::BuildQuality::kLbvh), cam, p);
  EXPECT_EQ(ra.verification, rb.verification);
  EXPECT_EQ(ra.image.data, rb.image.data);
  EXPECT_GT(ra.hits, 0);
  std::remove(text.c_str());
  std::remove(binary.c_str());
}

TEST(BakeRender, RejectsMapsThatAreNotBaked) {
  Mesh raw = square_map(10, direction_colour);
  raw.viewpoints = ViewpointColors();
  EXPECT_THROW(make_baked_map(raw, "raw.bs", true), InputError);
  Mesh uneven = square_map(10, direction_colour);
  uneven.viewpoints.offsets[1] -= 1;  // vertex 0 has 9 viewpoints
  try {
    make_baked_map(uneven, "uneven.bs", true);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("uneven.bs:1:"), std::string::npos) << e.what();
  }
  Mesh shuffled = square_map(10, direction_colour);
  std::swap(shuffled.viewpoints.dirs[11], shuffled.viewpoints.dirs[12]);  // vertex 1, views 1-2
  try {
    make_baked_map(shuffled, "shuffled.bs", true);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("shuffled.bs:14:"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rtmini::bake
