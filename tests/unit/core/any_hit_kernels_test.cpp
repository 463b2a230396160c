// The device any-hit kernels of bvh/any_hit_gpu.hpp (issue 21) against brute force and against
// the binary traversal they replace: every kernel, through its own driver (any_hit_all), gives
// every ray brute force's answer, and visits the binary traversal's nodes and triangles.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "rtmini/bvh/any_hit_gpu.hpp"
#include "rtmini/bvh/brute_force.hpp"
#include "rtmini/bvh/build.hpp"
#include "rtmini/bvh/gpu_collapse.hpp"
#include "rtmini/bvh/gpu_compact.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "test_space.hpp"

namespace rtmini::test {
namespace {

using Policy = Kokkos::RangePolicy<TestExecSpace>;
using Kernel = bvh::AnyHitKernel;

Kokkos::View<Triangle*, TestMemSpace> mesh_triangles(const std::string& name) {
  return upload_triangles(read_mesh(std::string(scenes_dir()) + "/" + name));
}

// AO-like rays: from points just off random triangles, cosine directions about the normal,
// a third of them with a short segment (the any-hit cases that end early and late).
Kokkos::View<Ray*, TestMemSpace> ao_like_rays(Kokkos::View<const Triangle*, TestMemSpace> tris,
                                              int n, std::uint64_t seed) {
  Kokkos::View<Ray*, TestMemSpace> rays("rays", n);
  const int nt = static_cast<int>(tris.extent(0));
  Kokkos::parallel_for(
      "test::ao_like_rays", Policy(0, n), KOKKOS_LAMBDA(int i) {
        const Rng rng(seed, std::uint64_t(i), 0);
        const auto b = rng.block(0);
        const Triangle t = tris(int(b.v[0] % std::uint32_t(nt)));
        Real u, v;
        uniform_triangle(Rng::to_unit(b.v[1]), Rng::to_unit(b.v[2]), u, v);
        Vec3 nrm = cross(t.b - t.a, t.c - t.a);
        nrm = length_squared(nrm) > Real(0) ? normalize(nrm) : Vec3(0, 0, 1);
        const Real scale = length(t.b - t.a) + Real(1e-6);
        Ray r;
        r.org = barycentric_point(t.a, t.b, t.c, u, v) + nrm * (Real(1e-3) * scale);
        r.dir = Frame(nrm).to_world(cosine_hemisphere(Rng::to_unit(b.v[3]), rng.uniform(4)));
        r.tmin = 0;
        r.tmax = i % 3 == 0 ? Real(20) * scale : Real(1e30);
        rays(i) = r;
      });
  return rays;
}

// Rays from random points of a box around the mesh in uniform directions.
Kokkos::View<Ray*, TestMemSpace> box_rays(const Aabb& box, int n, std::uint64_t seed) {
  Kokkos::View<Ray*, TestMemSpace> rays("rays", n);
  const Vec3 c = box.center(), e = box.extent() * Real(0.75);
  Kokkos::parallel_for(
      "test::box_rays", Policy(0, n), KOKKOS_LAMBDA(int i) {
        const Rng rng(seed, std::uint64_t(i), 0);
        const auto a = rng.block(0), b = rng.block(1);
        Ray r;
        r.org = c + Vec3(e.x * (2 * Rng::to_unit(a.v[0]) - 1), e.y * (2 * Rng::to_unit(a.v[1]) - 1),
                         e.z * (2 * Rng::to_unit(a.v[2]) - 1));
        r.dir = uniform_sphere(Rng::to_unit(b.v[0]), Rng::to_unit(b.v[1]));
        rays(i) = r;
      });
  return rays;
}

struct RayAt {
  Kokkos::View<Ray*, TestMemSpace> rays;
  KOKKOS_INLINE_FUNCTION Ray operator()(std::int64_t i) const { return rays(i); }
};
struct StoreAt {
  Kokkos::View<int*, TestMemSpace> out;
  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t i, bool blocked) const {
    out(i) = blocked ? 1 : 0;
  }
};

template <Kernel K, class Accel>
std::vector<int> any_hits(const Accel& accel, const Kokkos::View<Ray*, TestMemSpace>& rays) {
  const std::int64_t n = static_cast<std::int64_t>(rays.extent(0));
  Kokkos::View<int*, TestMemSpace> out("any", n);
  Kokkos::deep_copy(out, -1);  // a ray the driver skipped stays -1
  bvh::any_hit_all<K>(TestExecSpace(), accel, n, RayAt{rays}, StoreAt{out});
  std::vector<int> h;
  compat::download(out, h);
  return h;
}

// Node visits and triangle tests of every ray, summed (one kernel at a time, per-ray entry).
template <Kernel K, class Accel>
std::pair<double, double> work(const Accel& accel, const Kokkos::View<Ray*, TestMemSpace>& rays) {
  double nodes = 0, tests = 0;
  Kokkos::parallel_reduce(
      "test::any_hit_work", Policy(0, int(rays.extent(0))),
      KOKKOS_LAMBDA(int i, double& nn, double& tt) {
        bvh::TraversalStats st;
        bvh::any_hit<K>(accel, rays(i), st);
        nn += st.nodes;
        tt += st.tests;
      },
      nodes, tests);
  return {nodes, tests};
}

template <Kernel K, class Accel>
void expect_kernel_matches(const Accel& accel, const Kokkos::View<Ray*, TestMemSpace>& rays,
                           const std::vector<int>& ref, const std::string& what) {
  const std::vector<int> got = any_hits<K>(accel, rays);
  ASSERT_EQ(got.size(), ref.size());
  int mismatches = 0, blocked = 0;
  for (std::size_t i = 0; i < ref.size(); ++i) {
    blocked += ref[i];
    if (got[i] != ref[i] && ++mismatches <= 5)
      ADD_FAILURE() << what << " " << bvh::to_string(K) << " ray " << i << ": " << got[i]
                    << " vs reference " << ref[i];
  }
  EXPECT_EQ(mismatches, 0) << what << " " << bvh::to_string(K);
  EXPECT_GT(blocked, int(ref.size()) / 20) << what << ": too few blocked rays to mean much";
  EXPECT_LT(blocked, int(ref.size()) - int(ref.size()) / 20) << what << ": too few open rays";
}

template <Kernel... Ks, class Accel>
void expect_every_kernel_matches(const Accel& accel, const Kokkos::View<Ray*, TestMemSpace>& rays,
                                 const std::vector<int>& ref, const std::string& what) {
  (expect_kernel_matches<Ks>(accel, rays, ref, what), ...);
}

template <class Accel>
void expect_all_kernels_match(const Accel& accel, const Kokkos::View<Ray*, TestMemSpace>& rays,
                              const std::vector<int>& ref, const std::string& what) {
  expect_every_kernel_matches<Kernel::kDefault, Kernel::kWide, Kernel::kStored, Kernel::kShort8,
                              Kernel::kShort16, Kernel::kDefaultBounded, Kernel::kStoredBounded,
                              Kernel::kShared8, Kernel::kShared16, Kernel::kSpeculative,
                              Kernel::kSpeculativeShared16>(accel, rays, ref, what);
  // kWide's kernels with the compressed wide copy (built on devices already; on the host only
  // when asked).
  auto wide = accel;
  if (wide.qwide.extent(0) == 0) bvh::add_quantized_wide(TestExecSpace(), wide);
  expect_every_kernel_matches<Kernel::kWide, Kernel::kWideBounded, Kernel::kWideShared>(
      wide, rays, ref, what + " (compressed wide)");
  // The compact kernels with the 32-byte nodes (without them they trace the default).
  auto compact = accel;
  bvh::add_compact_binary(TestExecSpace(), compact);
  ASSERT_EQ(compact.compact.extent(0), compact.nodes.extent(0)) << what;
  expect_every_kernel_matches<Kernel::kCompact, Kernel::kCompactBounded, Kernel::kCompactShared16,
                              Kernel::kSpeculativeCompact>(compact, rays, ref,
                                                           what + " (32-byte nodes)");
}

class AnyHitKernelsVsBruteForce : public ::testing::TestWithParam<std::string> {};

TEST_P(AnyHitKernelsVsBruteForce, EveryRayEqual) {
  auto tris = mesh_triangles(GetParam());
  const bvh::BruteForce<TestMemSpace> brute{tris};
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah}) {
    const auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
    for (int set = 0; set < 2; ++set) {
      const auto rays =
          set == 0 ? ao_like_rays(tris, 20000, 31) : box_rays(accel.bounds, 20000, 37);
      const std::vector<int> ref = any_hits<Kernel::kDefault>(brute, rays);
      expect_all_kernels_match(accel, rays, ref,
                               GetParam() + " " + bvh::to_string(q) + (set ? " box" : " ao"));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(SmallMeshes, AnyHitKernelsVsBruteForce,
                         ::testing::Values("teapot.obj", "CornellBox-Original.obj"));

// On the dragon (deep trees: stacks past 16 entries) every kernel gives the binary traversal's
// answers, visiting exactly its nodes and triangles (same order: near child first).
TEST(AnyHitKernels, DragonMatchesBinaryTraversal) {
  auto tris = mesh_triangles("dragon.obj");
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah}) {
    auto binary = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
    binary.wide = {};  // the host's 8-wide copy: trace the binary tree itself, as devices do
    const auto rays = ao_like_rays(tris, 40000, 41);
    const std::vector<int> ref = any_hits<Kernel::kDefault>(binary, rays);
    expect_all_kernels_match(binary, rays, ref, std::string("dragon ") + bvh::to_string(q));
    const auto base = work<Kernel::kDefault>(binary, rays);
    for (const auto& w : {work<Kernel::kStored>(binary, rays), work<Kernel::kShort8>(binary, rays),
                          work<Kernel::kShort16>(binary, rays)}) {
      EXPECT_EQ(w.first, base.first) << "node visits, " << bvh::to_string(q);
      EXPECT_EQ(w.second, base.second) << "triangle tests, " << bvh::to_string(q);
    }
  }
}

// The speculative traversal as a lane of a warp that never agrees: each lane holds a leaf
// pending while it visits nodes up to the next leaf, the path no host run takes otherwise (a
// host thread is its own warp). Answers as brute force's.
struct SpeculateAlways {
  bvh::Bvh<TestMemSpace> accel;
  Kokkos::View<Ray*, TestMemSpace> rays;
  Kokkos::View<int*, TestMemSpace> out;
  KOKKOS_INLINE_FUNCTION void operator()(int i) const {
    using Stack = bvh::detail::ShortStack<0>;
    const bool blocked = bvh::detail::any_hit_speculative<false, false, bvh::Bvh<TestMemSpace>,
                                                          Stack, bvh::detail::NeverAllVote>(
        accel, rays(i), Stack{}, nullptr);
    out(i) = blocked ? 1 : 0;
  }
};

TEST(AnyHitKernels, SpeculationKeepsBruteForceAnswers) {
  auto tris = mesh_triangles("teapot.obj");
  const bvh::BruteForce<TestMemSpace> brute{tris};
  for (auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kSah}) {
    const auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), tris, q);
    const auto rays = ao_like_rays(tris, 20000, 43);
    const std::vector<int> ref = any_hits<Kernel::kDefault>(brute, rays);
    Kokkos::View<int*, TestMemSpace> out("out", rays.extent(0));
    Kokkos::parallel_for("test::speculate_always", Policy(0, int(rays.extent(0))),
                         SpeculateAlways{accel, rays, out});
    std::vector<int> got;
    compat::download(out, got);
    int mismatches = 0, blocked = 0;
    for (std::size_t i = 0; i < ref.size(); ++i) {
      mismatches += got[i] != ref[i] ? 1 : 0;
      blocked += ref[i];
    }
    EXPECT_EQ(mismatches, 0) << bvh::to_string(q);
    EXPECT_GT(blocked, int(ref.size()) / 20) << "too few blocked rays to mean much";
  }
}

// The short stack and the shared-memory ring are stacks at every depth: registers (or the
// ring), spill and refill.
template <class Stack>
void expect_last_in_first_out(Stack s, const std::string& what) {
  std::uint32_t deep[bvh::kStackSize];
  for (int round = 0; round < 2; ++round) {
    for (std::uint32_t v = 0; v < 40; ++v) s.push(1000 * round + v, deep);
    for (std::uint32_t v = 40; v-- > 20;) EXPECT_EQ(s.pop(deep), 1000u * round + v) << what;
    for (std::uint32_t v = 20; v < 30; ++v) s.push(5000 + v, deep);
    for (std::uint32_t v = 30; v-- > 20;) EXPECT_EQ(s.pop(deep), 5000u + v) << what;
    for (std::uint32_t v = 20; v-- > 0;) EXPECT_EQ(s.pop(deep), 1000u * round + v) << what;
    EXPECT_TRUE(s.empty()) << what;
  }
}

TEST(AnyHitKernels, ShortStackIsLastInFirstOut) {
  expect_last_in_first_out(bvh::detail::ShortStack<0>{}, "short 0");
  expect_last_in_first_out(bvh::detail::ShortStack<8>{}, "short 8");
  expect_last_in_first_out(bvh::detail::ShortStack<16>{}, "short 16");
}

// A thread's ring interleaved with its team's (stride 3, this thread second): it stays inside
// its own slots and is a stack.
TEST(AnyHitKernels, SharedRingIsLastInFirstOut) {
  std::uint32_t team_scratch[3 * 16 + 3];
  for (auto& w : team_scratch) w = 0xdeadbeefu;
  expect_last_in_first_out(bvh::detail::SharedRing<8, std::uint32_t>(team_scratch + 1, 3),
                           "ring 8");
  expect_last_in_first_out(bvh::detail::SharedRing<16, std::uint32_t>(team_scratch + 1, 3),
                           "ring 16");
  for (int j = 0; j < 3 * 16 + 3; ++j) {
    if (j % 3 != 1) {
      EXPECT_EQ(team_scratch[j], 0xdeadbeefu) << "another thread's word " << j;
    }
  }
}

// Every decoded box of the 32-byte nodes encloses its child's exact box, within two grid steps
// per plane (quantisation rounds outward by less than one step; the check may add one).
void expect_compact_boxes_enclose(const std::string& mesh, bvh::BuildQuality q) {
  auto accel = bvh::build<TestExecSpace, TestMemSpace>(TestExecSpace(), mesh_triangles(mesh), q);
  bvh::add_compact_binary(TestExecSpace(), accel);
  std::vector<bvh::BvhNode> nodes;
  std::vector<bvh::CompactBvhNode> compact;
  compat::download(accel.nodes, nodes);
  compat::download(accel.compact, compact);
  ASSERT_EQ(nodes.size(), compact.size());
  const bvh::CompactGrid& g = accel.grid;
  int loose = 0, wide = 0, checked = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(compact[i].child[k], nodes[i].child[k]);
      if (nodes[i].child[k] == bvh::kEmptyLeaf) continue;
      const Aabb exact = nodes[i].box(k), box = bvh::detail::compact_box(compact[i], g, k);
      ++checked;
      loose += bvh::detail::encloses(box, exact) ? 0 : 1;
      wide += (exact.lo.x - box.lo.x > 2 * g.step[0] || box.hi.x - exact.hi.x > 2 * g.step[0] ||
               exact.lo.y - box.lo.y > 2 * g.step[1] || box.hi.y - exact.hi.y > 2 * g.step[1] ||
               exact.lo.z - box.lo.z > 2 * g.step[2] || box.hi.z - exact.hi.z > 2 * g.step[2])
                  ? 1
                  : 0;
    }
  EXPECT_GT(checked, 0);
  EXPECT_EQ(loose, 0) << mesh << ": decoded boxes that miss part of their child";
  EXPECT_EQ(wide, 0) << mesh << ": decoded boxes more than two steps too large";
  // The grid spans the root's boxes with 2^16 planes: its step is under 2^-14 of the extent.
  const Vec3 e = accel.bounds.extent();
  EXPECT_LT(g.step[0], e.x / 16384);
  EXPECT_LT(g.step[1], e.y / 16384);
  EXPECT_LT(g.step[2], e.z / 16384);
}

TEST(AnyHitKernels, CompactBoxesEncloseTheirChildren) {
  expect_compact_boxes_enclose("teapot.obj", bvh::BuildQuality::kSah);
  expect_compact_boxes_enclose("dragon.obj", bvh::BuildQuality::kLbvh);
}

// A flat axis (all boxes in one plane) still decodes exactly onto that plane.
TEST(AnyHitKernels, CompactGridOfAFlatBox) {
  Aabb box;
  box.lo = Vec3(-1, 2, 3);
  box.hi = Vec3(5, 2, 3.5);
  const bvh::CompactGrid g = bvh::detail::compact_grid(box);
  EXPECT_EQ(bvh::grid_plane(g, 1, bvh::detail::count_below(g, 1, Real(2))), Real(2));
  EXPECT_EQ(bvh::grid_plane(g, 1, bvh::detail::count_above(g, 1, Real(2))), Real(2));
  EXPECT_GE(bvh::grid_plane(g, 0, bvh::kCompactGridMax), Real(5));
  EXPECT_GE(bvh::grid_plane(g, 2, bvh::kCompactGridMax), Real(3.5));
  EXPECT_LE(bvh::grid_plane(g, 0, bvh::detail::count_below(g, 0, Real(0.1))), Real(0.1));
  EXPECT_GE(bvh::grid_plane(g, 0, bvh::detail::count_above(g, 0, Real(0.1))), Real(0.1));
}

TEST(AnyHitKernels, NamesRoundTrip) {
  for (Kernel k : bvh::kAnyHitKernels) {
    Kernel back = Kernel::kDefault;
    EXPECT_TRUE(bvh::parse_any_hit_kernel(bvh::to_string(k), back));
    EXPECT_EQ(back, k);
  }
  Kernel unused;
  EXPECT_FALSE(bvh::parse_any_hit_kernel("short4", unused));
}

}  // namespace
}  // namespace rtmini::test
