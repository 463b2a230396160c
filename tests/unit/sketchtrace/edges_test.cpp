// The edge stencil draws each silhouette once (about h pixels wide, not 2h), and
// the renderer's output does not depend on how the pixels are cut into chunks.
#include <gtest/gtest.h>

#include "sketch_test_util.hpp"

namespace rtmini::sketch::test {
namespace {

HostScene sphere_scene() {
  HostScene scene;
  Material m;
  m.diffuse = Vec3f(0.6f);
  add_sphere(scene, Vec3d(0.0), 1.0, 4, m, "ball");
  return scene;
}

RenderSettings sphere_settings(double h) {
  RenderSettings s;
  s.width = 96;
  s.height = 96;
  s.spp = 1;
  s.bounces = 0;
  s.camera.position = Vec3d(0, 0, 4);
  s.camera.look_at = Vec3d(0, 0, 0);
  s.camera.fov_deg = 40;
  s.has_camera = true;
  s.edge_thickness = h;
  s.stencil_samples = 16;
  s.aov = {"edge", "object"};
  return s;
}

TEST(SketchEdges, SilhouetteIsDrawnOnceWithWidthAboutH) {
  const HostScene scene = sphere_scene();
  for (const double h : {2.0, 4.0}) {
    const RenderSettings s = sphere_settings(h);
    const auto px = render_all(scene, s);
    const int y = s.height / 2;
    // Integrated edge darkness across the row and the number of marked pixels, per crossing.
    double integral = 0;
    int marked = 0, outside_marked = 0;
    for (int x = 0; x < s.width; ++x) {
      const PixelResult& p = px[static_cast<std::size_t>(y) * s.width + x];
      integral += p.edge;
      if (p.edge > 0.02f) {
        ++marked;
        if (p.object < 0) ++outside_marked;
      }
    }
    const double per_crossing = integral / 2.0;
    std::printf("h=%.0f: %d marked pixels on the row (2 crossings), integral per crossing %.3f\n",
                h, marked, per_crossing);
    // One-sided marking: a ring point at distance d < h from the boundary crosses it with
    // 3/8 (d < h/sqrt2) or 1/8 of the 8 rays: integral ~ 0.3 h; doubling would give ~0.6 h.
    EXPECT_NEAR(per_crossing, 0.30 * h, 0.08 * h);
    EXPECT_LE(marked, 2 * static_cast<int>(h + 2));
    EXPECT_GE(marked, 2 * static_cast<int>(h - 1));
    // Background pixels (centre on the background) never mark the edge, up to anti-aliasing.
    EXPECT_LE(outside_marked, 2);
  }
}

TEST(SketchEdges, NoEdgesInsideASmoothSurface) {
  const HostScene scene = sphere_scene();
  const RenderSettings s = sphere_settings(2.0);
  const auto px = render_all(scene, s);
  const int c = s.width / 2;
  for (int y = c - 10; y <= c + 10; ++y)
    for (int x = c - 10; x <= c + 10; ++x)
      EXPECT_EQ(px[static_cast<std::size_t>(y) * s.width + x].edge, 0.f);
}

TEST(SketchChunks, ResultDoesNotDependOnChunking) {
  HostScene scene = sphere_scene();
  add_floor(scene, 5.0, 0.5f);
  add_quad_light(scene, Vec3d(-0.5, 3, -0.5), Vec3d(1, 0, 0), Vec3d(0, 0, 1), Vec3f(5.f));
  RenderSettings s = sphere_settings(1.5);
  s.width = 40;
  s.height = 30;
  s.spp = 3;
  s.shadow_samples = 5;
  s.camera.aperture = 0.1;
  s.camera.shutter_close = 1.0;
  s.camera.velocity = Vec3d(0.05, 0, 0);
  const Renderer r(scene, s);
  std::vector<PixelResult> whole;
  r.render({{0, 0, s.width, s.height}}, whole);
  // The same pixels in odd rectangles, in a scrambled order.
  const std::vector<PixelChunk> chunks = {{7, 11, 33, 19}, {0, 0, 40, 11}, {0, 11, 7, 19}};
  std::vector<PixelResult> parts;
  r.render(chunks, parts);
  std::size_t k = 0;
  for (const PixelChunk& c : chunks)
    for (int y = c.y0; y < c.y0 + c.h; ++y)
      for (int x = c.x0; x < c.x0 + c.w; ++x, ++k) {
        const PixelResult& a = whole[static_cast<std::size_t>(y) * s.width + x];
        const PixelResult& b = parts[k];
        ASSERT_EQ(a.r, b.r);
        ASSERT_EQ(a.g, b.g);
        ASSERT_EQ(a.b, b.b);
        ASSERT_EQ(a.edge, b.edge);
        ASSERT_EQ(a.rays, b.rays);
      }
  EXPECT_EQ(k, whole.size());
}

}  // namespace
}  // namespace rtmini::sketch::test
