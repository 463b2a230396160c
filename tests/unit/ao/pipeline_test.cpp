// Sample placement, determinism of the ray counts under any batch/pass/rank
// split, and the output layouts (.bin, .ply, .obj, .glb).
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ao_output.hpp"
#include "ao_test_util.hpp"
#include "ao_trace.hpp"
#include "rtmini/io/error.hpp"
#include "vertex_mapping.hpp"

namespace rtmini::ao {
namespace {

AoScene sphere_on_grid() {
  AoScene scene;
  Mesh m;
  append_grid(m, {-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 8, 8, -1, 0);
  append_icosphere(m, {0, 0.75, 0}, 0.7, 1, -1, 0);
  test::add_instance(scene, m);
  AoInstance copy = scene.instances[0];
  copy.xform = make_trs({5, 0, 0}, {0, 45, 0}, {1, 1, 1});
  scene.instances.push_back(copy);
  test::add_instance(scene, test::quad_mesh({-3, 2, -3}, {6, 0, 0}, {0, 0, 6}), AffineD{}, true);
  return scene;
}

TEST(AoSamples, MinimumPerFaceAndAreaProportionalExtras) {
  AoScene scene = sphere_on_grid();
  const SamplePlan base = plan_samples(scene, 0, 3);
  ASSERT_EQ(base.receivers.size(), 2u);  // the blocker receives nothing
  EXPECT_EQ(base.total_samples(), 3 * base.total_triangles());
  const std::int64_t want = base.total_samples() + 10000;
  const SamplePlan more = plan_samples(scene, want, 3);
  EXPECT_EQ(more.total_samples(), want);
  double area = 0;
  for (double a : more.areas) area += a;
  for (std::int64_t g = 0; g < more.total_triangles(); ++g) {
    const double extra = double(more.offsets[g + 1] - more.offsets[g] - 3);
    EXPECT_GE(extra, 0);
    EXPECT_NEAR(extra, 10000.0 * more.areas[g] / area, 1.0);
  }
}

TEST(AoTrace, CountsIndependentOfBatchPassAndRankSplit) {
  AoScene scene = sphere_on_grid();
  const Bounds b = scene.receiver_bounds();
  const DeviceScene device(scene, bvh::BuildQuality::kLbvh,
                           make_ground_plane(b.lo, b.hi, 1, 100, 0.03));
  const SamplePlan plan = plan_samples(scene, 0, 3);
  const DeviceSamplePlan dplan = upload_plan(scene, plan);
  TraceSettings s;
  s.rays = 40;  // not a square: 36 stratified + 4 random directions
  s.offset = Real(0.01 * b.max_extent());
  s.max_distance = Real(10 * b.max_extent());
  PhaseTimer timer;
  const std::int64_t n = plan.total_samples();
  const auto whole = trace_samples(device.query(), dplan, s, 0, n, timer);
  s.passes = 7;
  s.batch = 97;
  std::vector<std::uint16_t> split;
  for (int r = 0; r < 3; ++r) {  // three "ranks", contiguous ranges
    const auto part = trace_samples(device.query(), dplan, s, n * r / 3, n * (r + 1) / 3, timer);
    split.insert(split.end(), part.begin(), part.end());
  }
  EXPECT_EQ(whole, split);
  std::int64_t occluded = 0;
  for (auto h : whole) occluded += h;
  EXPECT_GT(occluded, 0);
  EXPECT_LT(occluded, n * s.rays);
}

// Three instances of one receiver-and-occluder mesh, moved apart beyond the maximum hit
// distance: identical geometry and identical occluders, so only the rays tell them apart.
// They share their sample points (one factorisation serves all), but their rays are keyed per
// instance, so their counts are independent estimates of one AO: they agree in mean within
// the Monte-Carlo error and are seldom equal point by point.
TEST(AoTrace, InstancesKeyTheirRaysSoNoiseIsNotRepeated) {
  AoScene scene;
  Mesh m;
  append_grid(m, {-2, 0, -2}, {0, 0, 4}, {4, 0, 0}, 8, 8, -1, 0);
  append_icosphere(m, {0, 0.75, 0}, 0.7, 1, -1, 0);
  test::add_instance(scene, m);
  for (double x : {20.0, 40.0}) {
    AoInstance copy = scene.instances[0];
    copy.xform = make_trs({x, 0, 0}, {0, 0, 0}, {1, 1, 1});
    scene.instances.push_back(copy);
  }
  const SamplePlan plan = plan_samples(scene, 3000, 3);
  ASSERT_EQ(plan.receivers.size(), 3u);
  const std::int64_t per = plan.offsets[plan.tri_base[1]];
  ASSERT_EQ(plan.total_samples(), 3 * per);  // identical instances, identical sample counts
  const Bounds b = scene.receiver_bounds();
  const DeviceScene device(scene, bvh::BuildQuality::kSah,
                           make_ground_plane(b.lo, b.hi, 1, 100, 0.03));
  TraceSettings s;
  s.rays = 64;
  s.offset = Real(1e-3);
  s.max_distance = Real(5);  // well short of the next instance
  s.coordinate_bound = Real(max_component(vabs(b.hi)));
  PhaseTimer timer;
  const auto hits = trace_samples(device.query(), upload_plan(scene, plan), s, 0, 3 * per, timer);
  std::vector<double> mean(3, 0.0);
  for (int r = 0; r < 3; ++r)
    for (std::int64_t i = 0; i < per; ++i) mean[r] += hits[r * per + i];
  for (double& x : mean) x /= double(per) * s.rays;
  // Occluded fraction per sample is at most 1: the per-ray binomial bound on the mean's error.
  const double std_error = std::sqrt(mean[0] * (1 - mean[0]) / (double(per) * s.rays));
  for (int r = 1; r < 3; ++r) {
    std::int64_t partial = 0, equal = 0;  // samples neither fully open nor fully occluded
    for (std::int64_t i = 0; i < per; ++i) {
      const int a = hits[i], c = hits[r * per + i];
      if ((a == 0 || a == s.rays) && (c == 0 || c == s.rays)) continue;
      ++partial;
      equal += a == c;
    }
    std::printf(
        "instance %d: occluded fraction %.4f vs %.4f; %lld of %lld partly occluded "
        "samples equal\n",
        r, mean[r], mean[0], static_cast<long long>(equal), static_cast<long long>(partial));
    ASSERT_GT(partial, per / 10);
    EXPECT_LT(double(equal), 0.5 * double(partial)) << "instance " << r << " repeats instance 0";
    EXPECT_NEAR(mean[r], mean[0], 6 * std_error) << "instance " << r;
  }
}

// The sphere-on-grid scene and a result of known values (nothing traced): what the writers read.
struct FilledResult {
  AoScene scene = sphere_on_grid();
  SamplePlan plan;
  AoResult result;
  FilledResult() {
    plan = plan_samples(scene, 0, 3);
    result.scene = &scene;
    result.plan = &plan;
    for (std::int64_t v = 0; v < plan.total_vertices(); ++v)
      result.values.push_back(float(v % 17) / 16.0f);
  }
};

TEST(AoOutput, BinLayout) {
  FilledResult b;
  const std::string path = ::testing::TempDir() + "ao_test.bin";
  write_ao_output(path, b.result, false);
  const std::string bytes = test::file_bytes(path);
  const std::size_t ni = b.plan.receivers.size(), nv = b.plan.total_vertices();
  ASSERT_EQ(bytes.size(), 16 + ni * 24 + nv * 4);
  std::uint64_t head[2];
  std::memcpy(head, bytes.data(), 16);
  EXPECT_EQ(head[0], ni);
  EXPECT_EQ(head[1], nv);
  std::uint64_t inst[3];
  std::memcpy(inst, bytes.data() + 16 + 24, 24);  // second receiver
  EXPECT_EQ(inst[0], 0u);                         // both receivers share stored mesh 0
  EXPECT_EQ(inst[1], std::uint64_t(b.plan.vertex_base[1]));
  EXPECT_EQ(inst[2], std::uint64_t(b.plan.vertex_base[2] - b.plan.vertex_base[1]));
  float last;
  std::memcpy(&last, bytes.data() + bytes.size() - 4, 4);
  EXPECT_EQ(last, b.result.values.back());
}

TEST(AoOutput, GlbIsValidGltf2) {
  FilledResult b;
  const std::string path = ::testing::TempDir() + "ao_test.glb";
  write_ao_output(path, b.result, false);
  const std::string bytes = test::file_bytes(path);
  std::uint32_t h[5];
  ASSERT_GE(bytes.size(), 20u);
  std::memcpy(h, bytes.data(), 20);
  EXPECT_EQ(h[0], 0x46546C67u);
  EXPECT_EQ(h[1], 2u);
  EXPECT_EQ(h[2], bytes.size());
  EXPECT_EQ(h[3] % 4, 0u);
  EXPECT_EQ(h[4], 0x4E4F534Au);
  const std::string json = bytes.substr(20, h[3]);
  EXPECT_TRUE(json.back() == ' ' || json.back() == '}');  // padded with spaces, never NULs
  const auto doc = nlohmann::json::parse(json);
  std::uint32_t bin[2];
  std::memcpy(bin, bytes.data() + 20 + h[3], 8);
  EXPECT_EQ(bin[1], 0x004E4942u);
  EXPECT_EQ(bin[0] % 4, 0u);
  EXPECT_EQ(20 + h[3] + 8 + bin[0], bytes.size());
  EXPECT_EQ(doc["buffers"][0]["byteLength"].get<std::size_t>(), bin[0]);
  EXPECT_EQ(doc["asset"]["version"], "2.0");
  EXPECT_EQ(doc["nodes"].size(), 2u);
  EXPECT_TRUE(doc["nodes"][1].contains("matrix"));
  // Both instances share one POSITION and one index accessor; each has its own COLOR_0.
  const auto& p0 = doc["meshes"][0]["primitives"][0];
  const auto& p1 = doc["meshes"][1]["primitives"][0];
  EXPECT_EQ(p0["attributes"]["POSITION"], p1["attributes"]["POSITION"]);
  EXPECT_EQ(p0["indices"], p1["indices"]);
  EXPECT_NE(p0["attributes"]["COLOR_0"], p1["attributes"]["COLOR_0"]);
  const auto& pos = doc["accessors"][p0["attributes"]["POSITION"].get<int>()];
  EXPECT_TRUE(pos.contains("min") && pos.contains("max"));
  for (const auto& v : doc["bufferViews"]) {
    EXPECT_EQ(v["byteOffset"].get<std::size_t>() % 4, 0u);
    EXPECT_LE(v["byteOffset"].get<std::size_t>() + v["byteLength"].get<std::size_t>(), bin[0]);
  }
}

TEST(AoOutput, PlyAndObjCounts) {
  FilledResult b;
  const std::string ply = ::testing::TempDir() + "ao_test.ply";
  write_ao_output(ply, b.result, true);
  const std::string text = test::file_bytes(ply);
  EXPECT_NE(text.find("element vertex " + std::to_string(b.plan.total_vertices())),
            std::string::npos);
  EXPECT_NE(text.find("element face " + std::to_string(b.plan.total_triangles())),
            std::string::npos);
  std::size_t lines = 0;
  for (char c : text) lines += c == '\n';
  const std::size_t header =
      std::count(text.begin(), text.begin() + text.find("end_header") + 11, '\n');
  EXPECT_EQ(lines - header, std::size_t(b.plan.total_vertices() + b.plan.total_triangles()));
  const std::string obj = ::testing::TempDir() + "ao_test.obj";
  write_ao_output(obj, b.result, false);
  const std::string o = test::file_bytes(obj);
  std::size_t v = 0, f = 0;
  std::istringstream in(o);
  for (std::string line; std::getline(in, line);) {
    v += line.rfind("v ", 0) == 0;
    f += line.rfind("f ", 0) == 0;
  }
  EXPECT_EQ(v, std::size_t(b.plan.total_vertices()));
  EXPECT_EQ(f, std::size_t(b.plan.total_triangles()));
  EXPECT_THROW(output_format("x.png"), InputError);
}

}  // namespace
}  // namespace rtmini::ao
