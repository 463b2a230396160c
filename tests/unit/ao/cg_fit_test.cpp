// The device CG fit (vertex_fit_cg.hpp) against the host sparse Cholesky (vertex_mapping.hpp):
// the same per-vertex AO within 1e-5 on the bundled AO scenes (instances, a blocker, the
// regulariser on and off, shared and separate systems), and the same per-receiver fallback.
#include <fenv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "ao_test_util.hpp"
#include "ao_trace.hpp"
#include "rtmini/io/error.hpp"
#include "vertex_fit_cg.hpp"
#include "vertex_mapping.hpp"

namespace rtmini::ao {
namespace {

double max_abs_diff(const std::vector<float>& a, const std::vector<float>& b) {
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    worst = std::max(worst, std::fabs(double(a[i]) - double(b[i])));
  return worst;
}

// A bundled scene traced as `bake ao` traces it (ground plane, default offsets), with few
// rays: noisy AO, the hard case for the fit.
struct Baked {
  AoScene scene;
  SamplePlan plan;
  std::vector<std::uint16_t> occluded;
  int rays = 0;
};

Baked bake_bundled(const std::string& name, int rays, int per_face) {
  Baked b;
  b.scene = load_ao_scene(std::string(RTMINI_AO_INPUTS_DIR) + "/" + name);
  const Bounds r = b.scene.receiver_bounds();
  const double extent = b.scene.scene_bounds().max_extent();
  const DeviceScene device(b.scene, bvh::BuildQuality::kLbvh,
                           make_ground_plane(r.lo, r.hi, 1, 100, 0.03));
  b.plan = plan_samples(b.scene, 0, per_face);
  TraceSettings s;
  s.rays = b.rays = rays;
  s.offset = Real(0.01 * extent);
  s.max_distance = Real(10 * extent);
  s.coordinate_bound = Real(2 * extent);
  PhaseTimer timer;
  b.occluded = trace_samples(device.query(), upload_plan(b.scene, b.plan), s, 0,
                             b.plan.total_samples(), timer);
  return b;
}

TEST(AoCgFit, MatchesCholeskyOnSpotInstances) {
  // Three Spot instances (two rigid, one uniformly scaled: one shared matrix) and a blocker.
  const Baked b = bake_bundled("spot_instances.toml", 8, 3);
  ASSERT_EQ(b.plan.receivers.size(), 3u);
  const SampleValues sv = make_sample_values(b.plan, 1, b.occluded, b.rays);
  for (const double w : {0.0, 0.1, 10.0}) {
    for (const bool share : {true, false}) {
      if (!share && w != 0.1) continue;  // separate systems: the same numbers, one case is enough
      LeastSquaresStats chol, cg;
      const auto x = map_least_squares(b.scene, sv, w, &chol, share, nullptr, FitMethod::kCholesky);
      const auto y = map_least_squares(b.scene, sv, w, &cg, share, nullptr, FitMethod::kCg);
      const double diff = max_abs_diff(x, y);
      std::printf("[ measured ] spot x3, w = %g, %s: CG %d iterations, max |CG - Cholesky| %.3g\n",
                  w, share ? "shared" : "separate", cg.cg_iterations, diff);
      EXPECT_EQ(cg.fallbacks, 0);
      EXPECT_EQ(chol.fallbacks, 0);
      EXPECT_EQ(cg.systems, chol.factorizations);
      EXPECT_EQ(cg.systems, share ? 1 : 3);
      EXPECT_GT(cg.cg_iterations, 0);
      EXPECT_LE(diff, 1e-5);
    }
  }
}

TEST(AoCgFit, MatchesCholeskyOnDragonInstances) {
  // Four dragon instances (100K triangles each, one matrix), one sample per face, random
  // visibility: every vertex's value comes from few, uncorrelated samples.
  AoScene scene = load_ao_scene(std::string(RTMINI_AO_INPUTS_DIR) + "/dragon_x4.toml");
  const SamplePlan plan = plan_samples(scene, 0, 1);
  SampleValues sv;
  sv.plan = &plan;
  sv.seed = 5;
  sv.visibility.resize(plan.total_samples());
  for (std::int64_t s = 0; s < plan.total_samples(); ++s) {
    float u, v;
    Rng(9, static_cast<std::uint64_t>(s), 0).uniform2(0, u, v);
    sv.visibility[s] = u;
  }
  for (const double w : {0.0, 0.1}) {
    LeastSquaresStats chol, cg;
    const auto x = map_least_squares(scene, sv, w, &chol, true, nullptr, FitMethod::kCholesky);
    const auto y = map_least_squares(scene, sv, w, &cg, true, nullptr, FitMethod::kCg);
    const double diff = max_abs_diff(x, y);
    std::printf("[ measured ] dragon x4, w = %g: CG %d iterations, max |CG - Cholesky| %.3g\n", w,
                cg.cg_iterations, diff);
    EXPECT_EQ(cg.fallbacks, chol.fallbacks);
    EXPECT_EQ(cg.systems, 1);
    EXPECT_LE(diff, 1e-5);
  }
}

double wavy(const Vec3d& p) { return 0.5 + 0.3 * std::sin(p.x) * std::cos(0.7 * p.y + p.z); }

TEST(AoCgFit, MatchesCholeskyWithSeveralMatrices) {
  // Three matrices in one batch: a grid + sphere mesh under two rigid transforms (shared) and a
  // non-uniform scale (its own relative areas), and a 64-triangle fan whose centre touches every
  // triangle, with an extra vertex no triangle uses (a row with the diagonal only).
  AoScene scene;
  Mesh m;
  append_grid(m, {-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 10, 10, -1, 0);
  append_icosphere(m, {0, 0.75, 0}, 0.7, 1, -1, 0);
  test::add_instance(scene, m, make_trs({1, 2, 3}, {10, 20, 30}, {1, 1, 1}));
  AoInstance copy = scene.instances[0];
  copy.xform = make_trs({7, -1, 4}, {0, 90, 0}, {1, 1, 1});
  scene.instances.push_back(copy);
  copy.xform = make_trs({0, 0, 9}, {0, 0, 0}, {1, 2, 1});
  scene.instances.push_back(copy);
  Mesh fan = test::disk_mesh(1.5, 0.0, 64);
  fan.positions.push_back({5, 5, 5});
  test::add_instance(scene, fan, make_trs({-6, 0, 0}, {90, 0, 0}, {1, 1, 1}));
  const SamplePlan plan = plan_samples(scene, 0, 3);
  SampleValues sv;
  sv.plan = &plan;
  sv.seed = 3;
  sv.visibility.resize(plan.total_samples());
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoInstance& inst = scene.instances[plan.receivers[r]];
    const AoMesh& mesh = scene.meshes[inst.mesh];
    for (std::int64_t g = plan.tri_base[r]; g < plan.tri_base[r + 1]; ++g) {
      const auto& t = mesh.tris[g - plan.tri_base[r]];
      for (std::int64_t s = plan.offsets[g]; s < plan.offsets[g + 1]; ++s) {
        Real u, v;
        sample_barycentrics(sv.seed, plan.item(r, g), s - plan.offsets[g], u, v);
        const Vec3d p = mesh.positions[t[0]] * (1.0 - u - v) + mesh.positions[t[1]] * double(u) +
                        mesh.positions[t[2]] * double(v);
        sv.visibility[s] = wavy(inst.xform.point(p));
      }
    }
  }
  for (const double w : {0.0, 0.1}) {
    LeastSquaresStats chol, cg;
    const auto x = map_least_squares(scene, sv, w, &chol, true, nullptr, FitMethod::kCholesky);
    const auto y = map_least_squares(scene, sv, w, &cg, true, nullptr, FitMethod::kCg);
    std::printf("[ measured ] 3 matrices, w = %g: CG %d iterations, max |CG - Cholesky| %.3g\n", w,
                cg.cg_iterations, max_abs_diff(x, y));
    EXPECT_EQ(chol.factorizations, 3);
    EXPECT_EQ(cg.systems, 3);
    EXPECT_EQ(cg.fallbacks, 0);
    EXPECT_LE(max_abs_diff(x, y), 1e-5) << "w = " << w;
    EXPECT_EQ(y.back(), 1.0f);  // the unused vertex: pulled to open, as by Cholesky
  }
}

// Bitwise equality that counts NaN == NaN.
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Invalid operations do not trap while one lives (the test main traps them; NaN data is the
// point of the test below).
struct QuietNan {
#if defined(__GLIBC__)
  int saved = fedisableexcept(FE_INVALID);
  ~QuietNan() { feenableexcept(saved); }
#endif
};

TEST(AoCgFit, FailedReceiverFallsBackToWeightedAverageAlone) {
  // A non-finite sample on the second Spot instance: its system has no solution, so both
  // methods hand that receiver (only) to the weighted average.
  const Baked b = bake_bundled("spot_instances.toml", 4, 3);
  const QuietNan quiet;
  SampleValues sv = make_sample_values(b.plan, 1, b.occluded, b.rays);
  sv.visibility[b.plan.offsets[b.plan.tri_base[1] + 10]] = std::nan("");
  const auto avg = map_weighted_average(b.scene, sv);
  std::vector<float> fits[2];
  for (const FitMethod m : {FitMethod::kCholesky, FitMethod::kCg}) {
    LeastSquaresStats st;
    auto x = map_least_squares(b.scene, sv, 0.1, &st, false, nullptr, m);
    EXPECT_EQ(st.fallbacks, 1) << fit_method_name(m);
    const auto v1 = b.plan.vertex_base[1], v2 = b.plan.vertex_base[2];
    EXPECT_TRUE(same_bits({x.begin() + v1, x.begin() + v2}, {avg.begin() + v1, avg.begin() + v2}));
    fits[m == FitMethod::kCg] = x;
  }
  EXPECT_LE(max_abs_diff({fits[0].begin(), fits[0].begin() + b.plan.vertex_base[1]},
                         {fits[1].begin(), fits[1].begin() + b.plan.vertex_base[1]}),
            1e-5);
}

TEST(AoCgFit, ParsesFitMethod) {
  EXPECT_EQ(parse_fit_method("cholesky"), FitMethod::kCholesky);
  EXPECT_EQ(parse_fit_method("cg"), FitMethod::kCg);
  const bool host = Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible;
  EXPECT_EQ(parse_fit_method("auto"), host ? FitMethod::kCholesky : FitMethod::kCg);
  EXPECT_THROW(parse_fit_method("lu"), InputError);
}

}  // namespace
}  // namespace rtmini::ao
