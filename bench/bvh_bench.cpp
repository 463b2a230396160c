// rtmini-bvh-bench: BVH build time and traversal throughput on a mesh for a
// fixed workload, optionally against Embree on the identical ray set.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <thread>

#include "ray_buffer.hpp"
#include "workload_file.hpp"
#include "rtmini/bvh/any_hit_gpu.hpp"
#include "rtmini/bvh/build.hpp"
#include "rtmini/bvh/gpu_compact.hpp"
#include "rtmini/bvh/quality.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/geometry/offset.hpp"
#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/parallel/ray_loop.hpp"
#include "rtmini/parallel/communicator.hpp"
#include "rtmini/report/app_main.hpp"
#include "rtmini/report/common_options.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/report/memory_check.hpp"
#include "rtmini/report/rank_timings.hpp"
#include "rtmini/report/run_report.hpp"
#include "rtmini/report/version.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"
#include "rtmini/scene/device_mesh.hpp"
#include "rtmini/scene/primitives.hpp"

namespace {

using namespace rtmini;
using Exec = Kokkos::DefaultExecutionSpace;
using Mem = Exec::memory_space;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string mesh;
  std::string workload = "ao";
  std::string quality = "sah";
  std::string peer;
  std::string write_workload;
  std::string camera = "framed";
  std::string gpu_trace = "default";
  std::string ray_order = "ray";
  std::string packets = "auto";
  bool peer_packets = false;
  std::string spatial_splits = bvh::to_string(bvh::kDefaultSpatialSplits);
  std::string time_builds = "lbvh,ploc,sah";
  bool build_phases = false;
  int copies = 1;
  std::string split_budget = bvh::split_budget_to_string(bvh::kDefaultSplitBudget);
  int samples_per_face = 3;
  int rays = 64;
  int width = 1024, height = 1024;
  int repeats = 3;
  std::uint64_t seed = 1;
  bool build_only = false;
  int settle_ms = 0;
};

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// CPU seconds of the whole process (all threads). On a machine shared with other jobs this
// counts the work done rather than the wait for a core, so paired CPU-time ratios stay
// meaningful under load where wall-clock ratios do not (OpenMP spin-waiting is counted too).
double cpu_seconds() { return double(std::clock()) / CLOCKS_PER_SEC; }

// --settle-ms: idle worker threads spin-wait for a while after each parallel region before they
// sleep (libgomp by default: ~7 ms here, results/bvh/README.md), and that CPU time lands in
// whatever is timed next. Sleeping `ms` before a timed build lets earlier work's workers fall
// asleep, and reading the CPU clock `ms` after it charges the build with its own workers' spin.
void settle(int ms) {
  if (ms > 0) std::this_thread::sleep_for(std::chrono::milliseconds(ms));
}

double best_of(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
double worst_of(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }
double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Each repeat's rtmini build against the peer build right after it (same machine load), as
// wall-clock and CPU-time ratios.
void print_paired_builds(const std::vector<double>& sah_s, const std::vector<double>& peer_s,
                         const std::vector<double>& sah_cpu, const std::vector<double>& peer_cpu) {
  std::vector<double> wall, cpu;
  for (std::size_t rep = 0; rep < sah_s.size(); ++rep) {
    wall.push_back(sah_s[rep] / peer_s[rep]);
    cpu.push_back(sah_cpu[rep] / peer_cpu[rep]);
  }
  std::printf(
      "paired builds (%zu repeats): sah %.2f ms vs embree %.2f ms wall, ratio median %.3f "
      "[%.3f, %.3f]; %.2f ms vs %.2f ms CPU, ratio median %.3f [%.3f, %.3f]\n",
      sah_s.size(), median_of(sah_s) * 1e3, median_of(peer_s) * 1e3, median_of(wall), best_of(wall),
      worst_of(wall), median_of(sah_cpu) * 1e3, median_of(peer_cpu) * 1e3, median_of(cpu),
      best_of(cpu), worst_of(cpu));
}

// A fingerprint of the tree's bytes (binary nodes, leaf triangle order, wide nodes and leaves):
// equal fingerprints mean a builder change left the tree exactly as it was.
template <class View>
std::uint64_t hash_bytes(std::uint64_t h, const View& v) {
  const auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v);
  const auto* bytes = reinterpret_cast<const unsigned char*>(host.data());
  const std::size_t n = host.span() * sizeof(typename View::value_type);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ bytes[i]) * 1099511628211ull;  // FNV-1a
  return h;
}

std::uint64_t tree_fingerprint(const bvh::Bvh<Mem>& accel) {
  std::uint64_t h = 14695981039346656037ull;
  h = hash_bytes(h, accel.nodes);
  h = hash_bytes(h, accel.prim);
  h = hash_bytes(h, accel.tris);
  h = hash_bytes(h, accel.wide);
  return hash_bytes(h, accel.leaves);
}

// The optional peer (--peer embree): inactive when none was asked for.
class Peer {
 public:
  Peer(const std::string& name, const Kokkos::View<Triangle*, Mem>& tris) {
    if (name.empty()) return;
    if (name != "embree") throw InputError("--peer must be embree, got '" + name + "'");
#ifdef RTMINI_HAVE_EMBREE
    auto ht = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tris);
    tris_.assign(ht.data(), ht.data() + ht.extent(0));
    embree_ = std::make_unique<bench::EmbreePeer>(tris_);
#else
    (void)tris;
    throw InputError(
        "--peer embree: this build has no Embree (install libembree-dev and reconfigure)");
#endif
  }
#ifdef RTMINI_HAVE_EMBREE
  bool active() const { return embree_ != nullptr; }
  double build() { return embree_->build(); }
  double trace(const std::vector<Ray>& rays, bool any, std::vector<int>& result,
               bool packets) const {
    return embree_->trace(rays, any, result, packets);
  }
  std::string version() const { return embree_->version(); }

 private:
  std::vector<Triangle> tris_;
  std::unique_ptr<bench::EmbreePeer> embree_;
#else
  bool active() const { return false; }
  double build() { return 0; }
  double trace(const std::vector<Ray>&, bool, std::vector<int>&, bool) const { return 0; }
  std::string version() const { return {}; }
#endif
};

// --write-workload: the triangles, the rays and this run's answers, for a peer built elsewhere
// (workload_file.hpp).
void write_workload_file(const std::string& path, const Kokkos::View<Triangle*, Mem>& tris,
                         const Kokkos::View<Ray*, Mem>& rays, const Kokkos::View<int*, Mem>& result,
                         bool any) {
  const auto ht = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tris);
  const auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rays);
  const auto ha = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), result);
  bench::WorkloadView w;
  w.tris = ht.data();
  w.num_tris = ht.extent(0);
  w.rays = hr.data();
  w.answers = ha.data();
  w.num_rays = hr.extent(0);
  w.any_hit = any;
  bench::write_workload(path, w);
  std::printf("workload written to %s (%llu triangles, %llu rays, %s answers)\n", path.c_str(),
              static_cast<unsigned long long>(w.num_tris),
              static_cast<unsigned long long>(w.num_rays), any ? "any-hit" : "closest-hit");
}

// A pinhole camera: rays from `eye` through a square image plane of half-width `tan_half`.
struct Camera {
  Vec3 eye;
  Vec3 forward, right, up;
  Real tan_half = Real(0.45);
};

KOKKOS_INLINE_FUNCTION Ray camera_ray(const Camera& cam, int x, int y, int w, int h) {
  const Real sx = (Real(2) * (x + Real(0.5)) / w - 1) * cam.tan_half;
  const Real sy = (1 - Real(2) * (y + Real(0.5)) / h) * cam.tan_half;
  Ray r;
  r.org = cam.eye;
  r.dir = normalize(cam.forward + cam.right * sx + cam.up * sy);
  r.tmin = 0;
  r.tmax = Real(1e30);
  return r;
}

Camera look_at(const Vec3& eye, const Vec3& target, Real tan_half) {
  const Frame f(normalize(target - eye));
  return {eye, f.n, f.t, f.b, tan_half};
}

// The whole bounding box in view from 1.4 diagonals away (the camera before issue 22: on the
// bundled meshes most of its rays miss, so it mostly measures empty space).
Camera overview_camera(const Aabb& box) {
  const Vec3 c = box.center();
  const Vec3 eye = c + normalize(Vec3(1, Real(0.6), Real(1.4))) * (Real(1.4) * box.diagonal());
  return look_at(eye, c, Real(0.45));
}

// Closest-hit distance of each of a probe x probe grid of the camera's rays (1e30: a miss).
std::vector<Real> probe_hits(const bvh::Bvh<Mem>& accel, const Camera& cam, int probe) {
  Kokkos::View<Real*, Mem> t("rtmini::bench::probe_t", std::size_t(probe) * probe);
  Kokkos::parallel_for(
      "rtmini::bench::probe_t", Kokkos::RangePolicy<Exec>(0, probe * probe), KOKKOS_LAMBDA(int i) {
        t(i) = bvh::closest_hit(accel, camera_ray(cam, i % probe, i / probe, probe, probe)).t;
      });
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), t);
  return std::vector<Real>(h.data(), h.data() + h.extent(0));
}

// The probe pixel deepest inside the mesh's silhouette (largest chessboard distance to a miss or
// the image border), so the narrowest field of view below still sees the widest patch.
int deepest_hit_pixel(const std::vector<Real>& t, int probe) {
  std::vector<int> d(t.size());
  for (int pass = 0; pass < 2; ++pass)
    for (int j = 0; j < probe * probe; ++j) {
      const int i = pass == 0 ? j : probe * probe - 1 - j;
      const int x = i % probe, y = i / probe, s = pass == 0 ? -1 : 1;
      if (t[i] >= Real(1e30)) {
        d[i] = 0;
        continue;
      }
      int m = pass == 0 ? probe : d[i];
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (dy == 0 && dx != -1) continue;  // the already-visited neighbours of this pass
          const int nx = x + s * -dx, ny = y + s * dy;
          const int nn = (nx < 0 || ny < 0 || nx >= probe || ny >= probe) ? 0 : d[ny * probe + nx];
          m = std::min(m, nn + 1);
        }
      d[i] = m;
    }
  return int(std::max_element(d.begin(), d.end()) - d.begin());
}

// The overview's eye aimed at the surface point deepest inside the mesh's silhouette, with the
// field of view narrowed in fixed steps until >= 95 % of a 64x64 probe of rays hit the mesh:
// primary rays that land on the surface (where secondary rays start), the same camera on every
// backend.
Camera framed_camera(const bvh::Bvh<Mem>& accel, const Aabb& box) {
  const Camera overview = overview_camera(box);
  constexpr int kProbe = 64;
  const std::vector<Real> t = probe_hits(accel, overview, kProbe);
  const int deepest = deepest_hit_pixel(t, kProbe);
  const Ray aim = camera_ray(overview, deepest % kProbe, deepest / kProbe, kProbe, kProbe);
  const Vec3 target =
      t[deepest] < Real(1e30) ? aim.org + aim.dir * t[deepest] : box.center();  // no hit: centre
  Camera cam = look_at(overview.eye, target, overview.tan_half);
  constexpr double kWantedHits = 0.95;
  while (cam.tan_half > Real(1e-3)) {
    const std::vector<Real> p = probe_hits(accel, cam, kProbe);
    const auto hits = std::count_if(p.begin(), p.end(), [](Real x) { return x < Real(1e30); });
    if (double(hits) >= kWantedHits * p.size()) break;
    cam.tan_half *= Real(0.85);
  }
  return cam;
}

Kokkos::View<Ray*, Mem> primary_rays(const Camera& cam, int w, int h) {
  Kokkos::View<Ray*, Mem> rays("rtmini::bench::primary_rays", std::size_t(w) * h);
  Kokkos::parallel_for(
      "rtmini::bench::gen_primary", Kokkos::RangePolicy<Exec>(0, w * h),
      KOKKOS_LAMBDA(int i) { rays(i) = camera_ray(cam, i % w, i / w, w, h); });
  return rays;
}

// Which ray the i-th thread traces: the rays' own order, or for
// --ray-order coherent (AO) ray k of up to kWarp neighbouring sample points side by side, so a
// warp's lanes trace from 32 nearby points (triangle order) instead of one point's 32 directions.
// The same rays either way; only which thread traces which changes.
struct RayOrder {
  static constexpr std::int64_t kWarp = 32;
  std::int64_t points = 0;
  std::int64_t rays = 1;  // per point
  bool coherent = false;

  KOKKOS_INLINE_FUNCTION std::int64_t operator()(std::int64_t i) const {
    if (!coherent) return i;
    const std::int64_t group = i / (kWarp * rays);  // kWarp points, the last group maybe fewer
    const std::int64_t base = group * kWarp;
    const std::int64_t width = points - base < kWarp ? points - base : kWarp;
    const std::int64_t within = i - group * kWarp * rays;
    const std::int64_t k = within / width;
    return (base + (within - k * width)) * rays + k;
  }
};

struct RayAt {
  Kokkos::View<Ray*, Mem> rays;
  RayOrder order;
  KOKKOS_INLINE_FUNCTION Ray operator()(std::int64_t i) const { return rays(order(i)); }
};

struct StoreBlocked {
  Kokkos::View<int*, Mem> result;
  RayOrder order;
  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t i, bool blocked) const {
    result(order(i)) = blocked ? 1 : 0;
  }
};

// The 32-byte node copy that the compact kernels trace, built (untimed: a variant under study,
// not part of any build figure) and its build time printed.
void add_compact_nodes(bvh::Bvh<Mem>& accel) {
  const auto t0 = Clock::now();
  bvh::add_compact_binary(Exec(), accel);
  Kokkos::fence();
  std::printf("compact nodes: %zu x 32 bytes built in %.2f ms (not timed with the trace)\n",
              accel.compact.extent(0), seconds_since(t0) * 1e3);
}

// The timed any-hit pass with the kernel chosen on the command line (--gpu-trace).
void trace_any(bvh::AnyHitKernel kernel, const bvh::Bvh<Mem>& accel,
               const Kokkos::View<Ray*, Mem>& rays, const Kokkos::View<int*, Mem>& result,
               const RayOrder& order) {
  const std::int64_t n = static_cast<std::int64_t>(rays.extent(0));
  const RayAt ray_at{rays, order};
  const StoreBlocked store{result, order};
  using K = bvh::AnyHitKernel;
  switch (kernel) {
    case K::kDefault:
      return bvh::any_hit_all<K::kDefault>(Exec(), accel, n, ray_at, store);
    case K::kWide:
      return bvh::any_hit_all<K::kWide>(Exec(), accel, n, ray_at, store);
    case K::kStored:
      return bvh::any_hit_all<K::kStored>(Exec(), accel, n, ray_at, store);
    case K::kShort8:
      return bvh::any_hit_all<K::kShort8>(Exec(), accel, n, ray_at, store);
    case K::kShort16:
      return bvh::any_hit_all<K::kShort16>(Exec(), accel, n, ray_at, store);
    case K::kDefaultBounded:
      return bvh::any_hit_all<K::kDefaultBounded>(Exec(), accel, n, ray_at, store);
    case K::kStoredBounded:
      return bvh::any_hit_all<K::kStoredBounded>(Exec(), accel, n, ray_at, store);
    case K::kCompactBounded:
      return bvh::any_hit_all<K::kCompactBounded>(Exec(), accel, n, ray_at, store);
    case K::kWideBounded:
      return bvh::any_hit_all<K::kWideBounded>(Exec(), accel, n, ray_at, store);
    case K::kShared8:
      return bvh::any_hit_all<K::kShared8>(Exec(), accel, n, ray_at, store);
    case K::kShared16:
      return bvh::any_hit_all<K::kShared16>(Exec(), accel, n, ray_at, store);
    case K::kWideShared:
      return bvh::any_hit_all<K::kWideShared>(Exec(), accel, n, ray_at, store);
    case K::kCompact:
      return bvh::any_hit_all<K::kCompact>(Exec(), accel, n, ray_at, store);
    case K::kCompactShared16:
      return bvh::any_hit_all<K::kCompactShared16>(Exec(), accel, n, ray_at, store);
    case K::kSpeculative:
      return bvh::any_hit_all<K::kSpeculative>(Exec(), accel, n, ray_at, store);
    case K::kSpeculativeShared16:
      return bvh::any_hit_all<K::kSpeculativeShared16>(Exec(), accel, n, ray_at, store);
    case K::kSpeculativeCompact:
      return bvh::any_hit_all<K::kSpeculativeCompact>(Exec(), accel, n, ray_at, store);
  }
}

// The timed pass in packets of bvh::kPacketSize consecutive rays (host memory only; the answers
// equal the single-ray pass's): result = 0/1 blocked (any hit) or the closest prim id.
template <class MemorySpace>
void trace_packets(const bvh::Bvh<MemorySpace>& accel, const Kokkos::View<Ray*, MemorySpace>& rays,
                   const Kokkos::View<int*, MemorySpace>& result, bool any) {
  if constexpr (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible) {
    constexpr std::int64_t kSize = bvh::kPacketSize;
    const std::int64_t n = static_cast<std::int64_t>(rays.extent(0));
    const Ray* all = rays.data();
    Kokkos::parallel_for(
        "rtmini::bench::trace_packets",
        RayLoopPolicy<Kokkos::DefaultHostExecutionSpace>(0, (n + kSize - 1) / kSize),
        [=](std::int64_t p) {
          const std::int64_t first = p * kSize;
          const int count = static_cast<int>(std::min(kSize, n - first));
          if (any) {
            bool blocked[kSize];
            bvh::any_hit_packet(accel, all + first, count, blocked);
            for (int r = 0; r < count; ++r) result(first + r) = blocked[r] ? 1 : 0;
          } else {
            Hit hits[kSize];
            bvh::closest_hit_packet(accel, all + first, count, hits);
            for (int r = 0; r < count; ++r) result(first + r) = hits[r].prim;
          }
        });
  } else {
    (void)accel, (void)rays, (void)result, (void)any;
    throw InputError("--packets on: host memory only");
  }
}

// The fixed AO workload: S samples per triangle at random barycentric points,
// R cosine-weighted rays each, origin offset 1e-4 x extent along the normal,
// maximum distance 10 x extent. Also returns per-sample areas for the mean AO.
Kokkos::View<Ray*, Mem> ao_rays(const DeviceMesh<Mem>& m, const Options& o, Real extent,
                                Kokkos::View<Real*, Mem>& area) {
  const int nt = static_cast<int>(m.tris.extent(0));
  const int S = o.samples_per_face, R = o.rays;
  Kokkos::View<Ray*, Mem> rays(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bench::ao_rays"),
      std::size_t(nt) * S * R);
  area = Kokkos::View<Real*, Mem>("rtmini::bench::ao_area", nt);
  const auto tris = m.tris;
  const std::uint64_t seed = o.seed;
  Kokkos::parallel_for(
      "rtmini::bench::gen_ao", Kokkos::RangePolicy<Exec>(0, nt * S), KOKKOS_LAMBDA(int ps) {
        const int t = ps / S;
        const Triangle tri = tris(t);
        const Vec3 n = triangle_normal(tri.a, tri.b, tri.c);
        if (ps % S == 0) area(t) = triangle_area(tri.a, tri.b, tri.c);
        const Rng point_rng(seed, std::uint64_t(ps), 0);
        float r1, r2;
        point_rng.uniform2(0, r1, r2);
        Real u, v;
        uniform_triangle(r1, r2, u, v);
        const Vec3 p = barycentric_point(tri.a, tri.b, tri.c, u, v);
        const Vec3 org = p + n * (Real(1e-4) * extent);
        const Frame f(n);
        for (int k = 0; k < R; ++k) {
          const Rng rng(seed, std::uint64_t(ps), std::uint32_t(k + 1));
          float a, b;
          rng.uniform2(0, a, b);
          Ray r;
          r.org = org;
          r.dir = f.to_world(cosine_hemisphere(a, b));
          r.tmin = 0;
          r.tmax = Real(10) * extent;
          rays(std::size_t(ps) * R + k) = r;
        }
      });
  return rays;
}

// Secondary rays from primary hits: shadow (any hit toward a point light) or diffuse (closest hit).
Kokkos::View<Ray*, Mem> secondary_rays(const DeviceMesh<Mem>& m,
                                       const Kokkos::View<Ray*, Mem>& prim, bool shadow,
                                       const Aabb& box, std::uint64_t seed) {
  const int n = static_cast<int>(prim.extent(0));
  Kokkos::View<Ray*, Mem> out("rtmini::bench::secondary_rays", n);
  const auto accel = m.accel;
  const auto tris = m.tris;
  const Real bound = m.coordinate_bound;
  const Vec3 light = box.center() + Vec3(Real(0.3), 1, Real(0.5)) * box.diagonal();
  Kokkos::parallel_for(
      "rtmini::bench::gen_secondary", Kokkos::RangePolicy<Exec>(0, n), KOKKOS_LAMBDA(int i) {
        const Ray pr = prim(i);
        const Hit h = bvh::closest_hit(accel, pr);
        Ray r;
        r.org = pr.org;
        r.dir = pr.dir;
        r.tmin = 0;
        r.tmax = -1;  // empty segment for rays that missed: traced but trivially rejected
        if (h.valid()) {
          const Triangle tri = tris(h.prim);
          Vec3 nrm = triangle_normal(tri.a, tri.b, tri.c);
          if (dot(nrm, pr.dir) > 0) nrm = -nrm;
          const Vec3 p =
              offset_ray_origin(barycentric_point(tri.a, tri.b, tri.c, h.u, h.v), nrm, bound);
          r.org = p;
          if (shadow) {
            const Vec3 d = light - p;
            r.tmax = length(d) * Real(0.9999);
            r.dir = normalize(d);
          } else {
            const Rng rng(seed, std::uint64_t(i), 0);
            float a, b;
            rng.uniform2(0, a, b);
            r.dir = Frame(nrm).to_world(cosine_hemisphere(a, b));
            r.tmax = Real(1e30);
          }
        }
        out(i) = r;
      });
  return out;
}

// "icosphere:L" makes a synthetic sphere of 20 * 4^L triangles (L = 8: 1.3M) for build scaling.
Mesh load_mesh(const std::string& spec) {
  const std::string prefix = "icosphere:";
  if (spec.rfind(prefix, 0) != 0) return read_mesh(spec);
  const int level = std::stoi(spec.substr(prefix.size()));
  if (level < 0 || level > 10)
    throw InputError("icosphere level must be 0..10, got " + std::to_string(level));
  Mesh m;
  append_icosphere(m, {0, 0, 0}, 1.0, level, -1, 0);
  return m;
}

// The 8-wide tree the host traverses (empty on devices): its size and how full its leaves are.
void print_wide_layout(const bvh::Bvh<Mem>& accel) {
  if (accel.wide.extent(0) == 0) return;
  const auto nodes = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), accel.wide);
  long long tris = 0;
  std::size_t leaves = 0, compact = 0;
  for (std::size_t i = 0; i < nodes.extent(0); ++i)
    for (int k = 0; k < bvh::kWidth; ++k) {
      const std::uint32_t c = nodes(i).child[k];
      if (!bvh::is_leaf(c) || c == bvh::kEmptyLeaf) continue;
      tris += bvh::leaf_count(c);
      ++leaves;
      compact += bvh::leaf_count(c) <= std::uint32_t(bvh::kCompactLeafSize) ? 1 : 0;
    }
  const double bytes = double(accel.wide.span()) * sizeof(bvh::WideNode) +
                       double(accel.leaves.span()) * sizeof(bvh::TriangleLanes);
  std::printf("wide tree: %zu nodes, %zu leaves (mean %.2f triangles, %zu compact), %.2f MiB\n",
              nodes.extent(0), leaves, double(tris) / std::max<std::size_t>(1, leaves), compact,
              bytes / (1 << 20));
}

// Which builders the benchmark times (--time-builds): the host SAH build of 10M triangles takes
// seconds, so device runs at that size leave it out.
struct TimedBuilds {
  bool lbvh = false, ploc = false, sah = false;
};

TimedBuilds parse_time_builds(const std::string& list) {
  TimedBuilds t;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t end = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, end - start);
    bvh::BuildQuality q;
    if (!bvh::parse_build_quality(name, q))
      throw InputError("--time-builds: expected a list of lbvh, ploc and sah, got '" + list + "'");
    if (q == bvh::BuildQuality::kLbvh)
      t.lbvh = true;
    else if (q == bvh::BuildQuality::kPloc)
      t.ploc = true;
    else
      t.sah = true;
    start = end + 1;
  }
  return t;
}

std::string build_ms(const char* name, bool timed, double seconds) {
  if (!timed) return "";
  char text[64];
  std::snprintf(text, sizeof text, " %s %.2f ms", name, seconds * 1e3);
  return text;
}

// Each device builder's phases (every phase fenced, so their sum is a little above the plain
// build time): the phases of the fastest of `repeats` builds.
void print_build_phases(const Kokkos::View<Triangle*, Mem>& tris, int repeats) {
  bvh::LbvhPhaseTimes lbvh;
  bvh::PlocPhaseTimes ploc;
  double lbvh_total = 1e300, ploc_total = 1e300;
  for (int rep = 0; rep < repeats; ++rep) {
    bvh::LbvhPhaseTimes l;
    bvh::build_lbvh<Exec, Mem>(Exec(), tris, &l);
    const double lt = l.bounds + l.morton + l.sort + l.hierarchy;
    if (lt < lbvh_total) {
      lbvh_total = lt;
      lbvh = l;
    }
    bvh::PlocPhaseTimes p;
    bvh::build_ploc<Exec, Mem>(Exec(), tris, &p);
    const double pt = p.front + p.cluster + p.emit;
    if (pt < ploc_total) {
      ploc_total = pt;
      ploc = p;
    }
  }
  std::printf(
      "lbvh phases (fastest of %d): bounds %.3f ms, morton %.3f ms, sort %.3f ms, hierarchy+refit "
      "%.3f ms; sum %.3f ms\n",
      repeats, lbvh.bounds * 1e3, lbvh.morton * 1e3, lbvh.sort * 1e3, lbvh.hierarchy * 1e3,
      lbvh_total * 1e3);
  std::printf(
      "ploc phases (fastest of %d): bounds+morton+sort %.3f ms, clustering %.3f ms (%d rounds, "
      "radius %d), layout %.3f ms; sum %.3f ms\n",
      repeats, ploc.front * 1e3, ploc.cluster * 1e3, ploc.rounds, bvh::kPlocRadius, ploc.emit * 1e3,
      ploc_total * 1e3);
}

// SAH cost (quality.hpp) of each timed builder's finished tree, the one traversal would get.
void print_sah_costs(const Kokkos::View<Triangle*, Mem>& tris, const TimedBuilds& timed,
                     double split_budget, bvh::SpatialSplits spatial) {
  std::printf("sah cost:");
  double sah = 0;
  if (timed.sah) {
    sah = bvh::measure_quality(bvh::build<Exec, Mem>(Exec(), tris, bvh::BuildQuality::kSah,
                                                     bvh::QuantizedWide::kNever, split_budget,
                                                     spatial))
              .sah_cost;
    std::printf(" sah %.3f", sah);
  }
  for (const auto q : {bvh::BuildQuality::kLbvh, bvh::BuildQuality::kPloc}) {
    if (!(q == bvh::BuildQuality::kLbvh ? timed.lbvh : timed.ploc)) continue;
    const auto b = bvh::build<Exec, Mem>(Exec(), tris, q, bvh::QuantizedWide::kNever);
    const double c = bvh::measure_quality(b).sah_cost;
    std::printf(" %s %.3f", bvh::to_string(q), c);
    if (b.quality != q) std::printf(" (too deep: built as %s)", bvh::to_string(b.quality));
    if (sah > 0) std::printf(" (%+.1f %% vs sah)", 100.0 * (c / sah - 1));
  }
  std::printf("\n");
}

// --copies N: the mesh N times on a cubic grid spaced 1.25 x its largest extent (100 dragons:
// 10M triangles), for builds and traces of real geometry at scale.
Mesh copies_on_grid(const Mesh& m, int copies) {
  if (copies <= 1) return m;
  Vec3d lo(1e300, 1e300, 1e300), hi(-1e300, -1e300, -1e300);
  for (const Vec3d& p : m.positions) {
    lo = Vec3d(std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z));
    hi = Vec3d(std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z));
  }
  const double step = 1.25 * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-30});
  int side = 1;
  while (side * side * side < copies) ++side;
  Mesh out = m;
  const int nv = static_cast<int>(m.positions.size());
  for (int c = 1; c < copies; ++c) {
    const Vec3d shift(step * (c % side), step * (c / side % side), step * (c / (side * side)));
    for (const Vec3d& p : m.positions) out.positions.push_back(p + shift);
    for (Face f : m.faces) {
      for (int k = 0; k < f.count; ++k) f.v[k] += c * nv;
      out.faces.push_back(f);
    }
  }
  return out;
}

// What the benchmark allocates after loading the mesh (report/memory_check.hpp): the uploaded
// mesh and BVH, the two timed rebuilds (LBVH and SAH) alive at once, the rays and their results
// (secondary workloads keep their primary rays), the peer's host copy of the rays.
MemoryNeed bench_memory_need(const Mesh& mesh, const Options& o) {
  const std::size_t nt = mesh.triangle_count();
  const double rays = o.workload == "ao" ? static_cast<double>(nt) * o.samples_per_face * o.rays
                                         : static_cast<double>(o.width) * o.height;
  const bool secondary = o.workload == "shadow" || o.workload == "diffuse";
  MemoryNeed need;
  need.views = device_mesh_bytes(nt, mesh.positions.size()) + 2 * bvh_bytes(nt) +
               rays * ((secondary ? 2 : 1) * sizeof(Ray) + sizeof(int)) +
               (o.workload == "ao" ? static_cast<double>(nt) * sizeof(Real) : 0.0);
  if (!o.peer.empty()) need.host = rays * (sizeof(Ray) + sizeof(int));
  // --write-workload: host copies of the rays and answers (the triangles are small beside them).
  if (!o.write_workload.empty()) need.host = std::max(need.host, rays * (sizeof(Ray) + sizeof(int)));
  return need;
}

int run(const Options& o, RunReport& report, const Communicator& comm, std::int64_t limit) {
  report.timer.start("load");
  const Mesh mesh = copies_on_grid(load_mesh(o.mesh), o.copies);
  report.timer.stop();
  const MemoryPeak peak = require_memory(comm, bench_memory_need(mesh, o), limit);
  report.scene["memory_estimate_bytes"] = comm.max(peak.host + peak.device);
  if (!o.write_workload.empty()) {  // refused before any work, like every output
    if (o.build_only) throw InputError("--write-workload: --build-only traces no rays");
    const std::uint64_t nt = mesh.triangle_count();
    const std::uint64_t nr = o.workload == "ao" ? nt * o.samples_per_face * o.rays
                                                : std::uint64_t(o.width) * o.height;
    check_output_place(o.write_workload, double(bench::workload_file_bytes(nt, nr)));
  }
  bvh::BuildQuality quality;
  if (o.quality == "auto") {  // the rule of build_quality.hpp, for this workload's rays
    const double nt = static_cast<double>(mesh.triangle_count());
    const double rays = o.workload == "ao" ? nt * o.samples_per_face * o.rays
                                           : static_cast<double>(o.width) * o.height;
    quality = bvh::choose_build_quality(nt, rays, compat::kDeviceMemory);
    std::printf("auto: %s for %.3g rays per triangle\n", bvh::to_string(quality), rays / nt);
  } else if (!bvh::parse_build_quality(o.quality, quality)) {
    throw InputError("--quality must be lbvh, ploc, sah or auto, got '" + o.quality + "'");
  }
  const TimedBuilds timed = parse_time_builds(o.time_builds);
  bvh::SpatialSplits spatial;
  if (!bvh::parse_spatial_splits(o.spatial_splits, spatial))
    throw InputError("--spatial-splits must be off, on or auto, got '" + o.spatial_splits + "'");
  double split_budget;
  if (!bvh::parse_split_budget(o.split_budget, split_budget))
    throw InputError("--split-budget must be auto or a number >= 0, got '" + o.split_budget + "'");
  const bool any = o.workload == "ao" || o.workload == "shadow";
  bvh::AnyHitKernel kernel;
  if (!bvh::parse_any_hit_kernel(o.gpu_trace, kernel))
    throw InputError("--gpu-trace must be one of " + bvh::any_hit_kernel_names() + ", got '" +
                     o.gpu_trace + "'");
  if (kernel != bvh::AnyHitKernel::kDefault && !any)
    throw InputError("--gpu-trace " + o.gpu_trace + ": only the any-hit workloads (ao, shadow)");
  if (o.ray_order != "ray" && o.ray_order != "coherent")
    throw InputError("--ray-order must be ray or coherent, got '" + o.ray_order + "'");
  if (o.ray_order == "coherent" && o.workload != "ao")
    throw InputError("--ray-order coherent: only the ao workload");
  if (o.packets != "auto" && o.packets != "on" && o.packets != "off")
    throw InputError("--packets must be auto, on or off, got '" + o.packets + "'");
  // Packets on the host (a device traces ray by ray), for every workload: they pay on the
  // coherent camera and shadow rays and, less, on the incoherent AO and diffuse rays, whose eight
  // independent tests per node overlap their latencies (results/bvh/README.md).
  const bool host_memory = Kokkos::SpaceAccessibility<Kokkos::HostSpace, Mem>::accessible;
  const bool packets =
      o.packets == "on" || (o.packets == "auto" && host_memory &&
                            kernel == bvh::AnyHitKernel::kDefault && o.ray_order == "ray");
  if (packets && (kernel != bvh::AnyHitKernel::kDefault || o.ray_order != "ray"))
    throw InputError("--packets on: only with the default any-hit kernel and ray order");

  std::cout << build_banner() << "\n";
  std::cout << "threads " << compat::concurrency() << ", mesh " << o.mesh << ": "
            << mesh.positions.size() << " vertices, " << mesh.triangle_count() << " triangles\n";

  // The SAH tree is built below with the split settings asked for (the cheap LBVH until then,
  // so that no second SAH tree is alive at the peak).
  DeviceMesh<Mem> dm =
      upload_mesh(mesh, quality == bvh::BuildQuality::kSah ? bvh::BuildQuality::kLbvh : quality);
  if (quality == bvh::BuildQuality::kSah)
    dm.accel = bvh::build<Exec, Mem>(Exec(), dm.tris, quality, bvh::QuantizedWide::kOnDevices,
                                     split_budget, spatial);
  const int repeats = std::max(1, o.repeats);
  Peer peer(o.peer, dm.tris);
  // Build timings: the best of several builds of the already-uploaded triangles (the raw LBVH
  // and PLOC builders; the SAH build whole, as it runs on the host), each repeat followed by the
  // peer's build of the same triangles. One rebuild is alive at a time.
  if (peer.active() && !timed.sah) throw InputError("--peer needs sah in --time-builds");
  double lbvh_s = 1e300, ploc_s = 1e300;
  std::vector<double> sah_s, peer_build_s, sah_cpu, peer_build_cpu;
  for (int rep = 0; rep < repeats; ++rep) {
    if (timed.lbvh) {
      const auto t0 = Clock::now();
      const auto b = bvh::build_lbvh<Exec, Mem>(Exec(), dm.tris);
      Kokkos::fence();
      lbvh_s = std::min(lbvh_s, seconds_since(t0));
    }
    if (timed.ploc) {
      const auto t0 = Clock::now();
      const auto b = bvh::build_ploc<Exec, Mem>(Exec(), dm.tris);
      Kokkos::fence();
      ploc_s = std::min(ploc_s, seconds_since(t0));
    }
    if (timed.sah) {
      settle(o.settle_ms);
      const auto t0 = Clock::now();
      double c0 = cpu_seconds();
      const auto b = bvh::build<Exec, Mem>(Exec(), dm.tris, bvh::BuildQuality::kSah,
                                           bvh::QuantizedWide::kOnDevices, split_budget, spatial);
      Kokkos::fence();
      sah_s.push_back(seconds_since(t0));
      settle(o.settle_ms);
      sah_cpu.push_back(cpu_seconds() - c0);
      if (peer.active()) {
        c0 = cpu_seconds();
        peer_build_s.push_back(peer.build());
        settle(o.settle_ms);
        peer_build_cpu.push_back(cpu_seconds() - c0);
      }
    }
  }
  const auto q = bvh::measure_quality(dm.accel);
  std::printf("build:%s%s%s; traced with %s: %s\n", build_ms("lbvh", timed.lbvh, lbvh_s).c_str(),
              build_ms("ploc", timed.ploc, ploc_s).c_str(),
              build_ms("sah", timed.sah, timed.sah ? best_of(sah_s) : 0).c_str(),
              bvh::to_string(quality), q.to_string().c_str());
  if (o.build_phases) print_build_phases(dm.tris, repeats);
  print_sah_costs(dm.tris, timed, split_budget, spatial);

  std::printf("sah splits: spatial %s, budget %s; %d leaf triangles (%d input)\n",
              o.spatial_splits.c_str(), o.split_budget.c_str(), dm.accel.num_prims,
              int(dm.tris.extent(0)));
  print_wide_layout(dm.accel);
  if (o.build_only) {
    if (peer.active()) print_paired_builds(sah_s, peer_build_s, sah_cpu, peer_build_cpu);
    std::printf("tree fingerprint %s\n", hash_hex(tree_fingerprint(dm.accel)).c_str());
    // The figure of merit: the SAH build's median, else the fastest device build timed (with no
    // SAH build timed there is no median to take).
    report.fom_unit = "ms";
    if (!sah_s.empty()) {
      report.fom_name = "median SAH build time";
      report.fom_value = median_of(sah_s) * 1e3;
    } else if (timed.lbvh || timed.ploc) {
      report.fom_name = timed.lbvh ? "best LBVH build time" : "best PLOC build time";
      report.fom_value = (timed.lbvh ? lbvh_s : ploc_s) * 1e3;
    }
    return 0;
  }

  const Aabb box = dm.accel.bounds;
  const Real extent = box.diagonal();
  Kokkos::View<Real*, Mem> area;
  Kokkos::View<Ray*, Mem> rays;
  // Ray generation (for shadow and diffuse: including the primary rays they start from) is
  // timed on its own, outside the traversal rate.
  report.timer.start("rays");
  const auto gen0 = Clock::now();
  Camera cam;
  if (o.workload != "ao") {
    if (o.camera == "framed")
      cam = framed_camera(dm.accel, box);
    else if (o.camera == "overview")
      cam = overview_camera(box);
    else
      throw InputError("--camera must be framed or overview, got '" + o.camera + "'");
  }
  if (o.workload == "ao") {
    rays = ao_rays(dm, o, extent, area);
    std::printf(
        "workload ao: %d samples/triangle x %d cosine rays, offset 1e-4 x extent, tmax 10 x extent "
        "(extent = bbox diagonal %.6g), any hit\n",
        o.samples_per_face, o.rays, double(extent));
  } else if (o.workload == "primary") {
    rays = primary_rays(cam, o.width, o.height);
    std::printf("workload primary: %dx%d %s camera rays (tan half-angle %.4g), closest hit\n",
                o.width, o.height, o.camera.c_str(), double(cam.tan_half));
  } else if (o.workload == "shadow" || o.workload == "diffuse") {
    rays = secondary_rays(dm, primary_rays(cam, o.width, o.height), o.workload == "shadow", box,
                          o.seed);
    std::printf(
        "workload %s: from the hits of %dx%d %s camera rays (tan half-angle %.4g), %s\n",
        o.workload.c_str(), o.width, o.height, o.camera.c_str(), double(cam.tan_half),
        o.workload == "shadow" ? "any hit toward a point light" : "cosine bounce, closest hit");
  } else {
    throw InputError("--workload must be primary, shadow, ao or diffuse, got '" + o.workload + "'");
  }
  Kokkos::fence();
  const double gen_s = seconds_since(gen0);
  report.timer.stop();
  const long long nr = static_cast<long long>(rays.extent(0));
  std::printf("ray generation: %lld rays in %.2f ms (not in the traversal rate)\n", nr,
              gen_s * 1e3);
  Kokkos::View<int*, Mem> result(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bench::result"), nr);
  auto accel = dm.accel;
  if (any && bvh::traces_compact_nodes(kernel)) add_compact_nodes(accel);
  RayOrder order;
  order.coherent = o.ray_order == "coherent";
  order.rays = o.rays;
  order.points = static_cast<std::int64_t>(dm.tris.extent(0)) * o.samples_per_face;
  if (any)
    std::printf("any-hit kernel %s, ray order %s\n", bvh::to_string(kernel), o.ray_order.c_str());
  std::printf("traced %s\n", packets ? "in packets of 8 consecutive rays" : "ray by ray");
  std::vector<Ray> host_rays;
  if (peer.active()) {
    auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rays);
    host_rays.assign(hr.data(), hr.data() + nr);
  }
  // Timed passes, each followed by the peer's pass over the same rays.
  std::vector<double> trace_s, peer_trace_s, trace_cpu, peer_trace_cpu;
  std::vector<int> peer_result;
  for (int rep = 0; rep < repeats; ++rep) {
    Kokkos::fence();
    const auto t0 = Clock::now();
    const double c0 = cpu_seconds();
    if (packets) {
      trace_packets(accel, rays, result, any);
    } else if (any) {
      trace_any(kernel, accel, rays, result, order);
    } else {
      Kokkos::parallel_for(
          "rtmini::bench::trace_closest", RayLoopPolicy<Exec>(0, nr),
          KOKKOS_LAMBDA(long long i) { result(i) = bvh::closest_hit(accel, rays(i)).prim; });
    }
    Kokkos::fence();
    trace_s.push_back(seconds_since(t0));
    trace_cpu.push_back(cpu_seconds() - c0);
    if (peer.active()) {
      const double c1 = cpu_seconds();
      peer_trace_s.push_back(peer.trace(host_rays, any, peer_result, o.peer_packets));
      peer_trace_cpu.push_back(cpu_seconds() - c1);
    }
  }
  const double best = best_of(trace_s);
  std::uint64_t hash = 0;
  Kokkos::parallel_reduce(
      "rtmini::bench::hash", Kokkos::RangePolicy<Exec>(0, nr),
      KOKKOS_LAMBDA(long long i, std::uint64_t& h) {
        h += hash_term(std::uint64_t(i), std::uint64_t(std::int64_t(result(i))));
      },
      hash);
  const double mrays = nr / best * 1e-6;
  long long hits = 0;
  Kokkos::parallel_reduce(
      "rtmini::bench::hits", Kokkos::RangePolicy<Exec>(0, nr),
      KOKKOS_LAMBDA(long long i, long long& n) { n += any ? result(i) : result(i) >= 0; }, hits);
  // Secondary rays of camera rays that missed have an empty segment: counted as misses.
  std::printf("hit fraction: %.4f (%lld of %lld rays %s)\n", double(hits) / std::max(1LL, nr), hits,
              nr, any ? "blocked" : "hit something");
  {
    // Untimed pass counting node visits and ray-triangle tests per ray.
    double nodes = 0, tests = 0;
    Kokkos::parallel_reduce(
        "rtmini::bench::stats", Kokkos::RangePolicy<Exec>(0, nr),
        KOKKOS_LAMBDA(long long i, double& nn, double& tt) {
          bvh::TraversalStats st;
          if (any)
            bvh::any_hit(accel, rays(i), st);
          else
            bvh::closest_hit(accel, rays(i), st);
          nn += st.nodes;
          tt += st.tests;
        },
        nodes, tests);
    std::printf("per ray: %.1f nodes visited, %.1f triangle tests (brute force: %d)\n", nodes / nr,
                tests / nr, dm.accel.num_prims);
  }
  std::printf("rays %lld, trace %.4f s (best of %d), %.2f Mrays/s\n", nr, best, o.repeats, mrays);

  if (o.workload == "ao") {
    const int R = o.rays, S = o.samples_per_face;
    double num = 0, den = 0;
    Kokkos::parallel_reduce(
        "rtmini::bench::mean_ao", Kokkos::RangePolicy<Exec>(0, int(area.extent(0))),
        KOKKOS_LAMBDA(int t, double& n, double& d) {
          int occluded = 0;
          for (long long k = std::int64_t(t) * S * R; k < std::int64_t(t + 1) * S * R; ++k)
            occluded += result(k);
          n += double(area(t)) * (1.0 - double(occluded) / (S * R));
          d += double(area(t));
        },
        num, den);
    std::printf("area-weighted mean AO (unoccluded fraction): %.6f\n", den > 0 ? num / den : 0.0);
  }

  if (peer.active()) {
    auto hres = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), result);
    long long agree = 0;
    for (long long i = 0; i < nr; ++i) agree += peer_result[i] == hres(i);
    const double peer_best = best_of(peer_trace_s);
    const double peer_mrays = nr / peer_best * 1e-6;
    std::printf("peer embree %s: build %.2f ms, trace %.4f s, %.2f Mrays/s; agreement %.5f%%\n",
                peer.version().c_str(), best_of(peer_build_s) * 1e3, peer_best, peer_mrays,
                100.0 * agree / std::max(1LL, nr));
    std::printf("ratio rtmini/embree: %.3f\n", mrays / peer_mrays);
    // Each repeat's rtmini pass against the peer pass right after it (same machine load).
    std::vector<double> trace_ratio, build_ratio, trace_cpu_ratio, build_cpu_ratio;
    for (int rep = 0; rep < repeats; ++rep) {
      trace_ratio.push_back(peer_trace_s[rep] / trace_s[rep]);
      build_ratio.push_back(sah_s[rep] / peer_build_s[rep]);
      trace_cpu_ratio.push_back(peer_trace_cpu[rep] / trace_cpu[rep]);
      build_cpu_ratio.push_back(sah_cpu[rep] / peer_build_cpu[rep]);
    }
    std::printf(
        "paired (%d repeats): speed ratio rtmini/embree median %.3f [%.3f, %.3f]; "
        "sah build median %.2f ms vs embree %.2f ms, time ratio median %.3f [%.3f, %.3f]\n",
        repeats, median_of(trace_ratio), best_of(trace_ratio), worst_of(trace_ratio),
        median_of(sah_s) * 1e3, median_of(peer_build_s) * 1e3, median_of(build_ratio),
        best_of(build_ratio), worst_of(build_ratio));
    std::printf(
        "paired CPU time (%d repeats): speed ratio rtmini/embree median %.3f [%.3f, %.3f]; "
        "sah build %.2f ms vs embree %.2f ms CPU, time ratio median %.3f [%.3f, %.3f]\n",
        repeats, median_of(trace_cpu_ratio), best_of(trace_cpu_ratio), worst_of(trace_cpu_ratio),
        median_of(sah_cpu) * 1e3, median_of(peer_build_cpu) * 1e3, median_of(build_cpu_ratio),
        best_of(build_cpu_ratio), worst_of(build_cpu_ratio));
  }
  if (!o.write_workload.empty()) write_workload_file(o.write_workload, dm.tris, rays, result, any);
  std::printf("FOM %.3f Mrays/s (%s, %s) verification %s\n", mrays, o.workload.c_str(),
              bvh::to_string(quality), hash_hex(hash).c_str());
  report.fom_name = "traversal rate";
  report.fom_unit = "Mrays/s";
  report.fom_value = mrays;
  report.verification_hash = hash;
  return 0;
}

int bench_main(Communicator& comm, int argc, char** argv) {
  Options o;
  CLI::App app{"rtmini-bvh-bench: BVH build and traversal throughput", "rtmini-bvh-bench"};
  CommonOptions common;
  add_common_options(app, common);
  app.add_option("mesh", o.mesh, "OBJ or .bs mesh, or icosphere:L (20*4^L triangles)")->required();
  app.add_option("--workload", o.workload, "primary, shadow, ao or diffuse")->capture_default_str();
  app.add_option("--quality", o.quality, "BVH build used for tracing: lbvh, ploc, sah or auto")
      ->capture_default_str();
  app.add_option("--time-builds", o.time_builds,
                 "builders whose build time and SAH cost are measured (comma-separated)")
      ->capture_default_str();
  app.add_option("--copies", o.copies, "trace the mesh this many times, on a grid")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_flag("--build-phases", o.build_phases,
               "print the LBVH and PLOC phase times (each phase fenced)");
  app.add_option("--samples-per-face", o.samples_per_face, "AO sample points per triangle")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--rays", o.rays, "AO rays per sample point")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--width", o.width, "camera width (primary/shadow/diffuse)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--height", o.height, "camera height")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--repeats", o.repeats, "timed repetitions (best is reported)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", o.seed, "random seed")->capture_default_str();
  app.add_option("--camera", o.camera,
                 "primary/shadow/diffuse camera: framed (>= 95 % of a probe grid on the mesh) or "
                 "overview (the whole bounding box, mostly misses)")
      ->capture_default_str();
  app.add_option("--spatial-splits", o.spatial_splits,
                 "SAH build: spatial splits off, on, or auto (the builder's default)")
      ->capture_default_str();
  app.add_option("--split-budget", o.split_budget,
                 "SAH build: extra references for slivers, as a fraction of the triangles, or "
                 "auto (grown while the SAH says it pays: bvh/presplit.hpp)")
      ->capture_default_str();
  app.add_option("--gpu-trace", o.gpu_trace,
                 "any-hit kernel (issue 21): default (today's dispatch) or a variant of "
                 "bvh/any_hit_gpu.hpp: " +
                     bvh::any_hit_kernel_names())
      ->capture_default_str();
  app.add_option("--ray-order", o.ray_order,
                 "ao: which rays a warp traces together: ray (one point's directions) or "
                 "coherent (ray k of 32 neighbouring points)")
      ->capture_default_str();
  app.add_option("--packets", o.packets,
                 "timed pass in packets of 8 consecutive rays: auto (on the host), on or off "
                 "(ray by ray); the answers are the same")
      ->capture_default_str();
  app.add_option("--peer", o.peer, "trace the identical rays with a peer: embree");
  app.add_option("--write-workload", o.write_workload,
                 "write the triangles, the rays and rtmini's answers to this file (flat binary, "
                 "bench/workload_file.hpp) for a peer built outside rtmini");
  app.add_flag("--peer-packets", o.peer_packets,
               "the peer traces in packets of 8 consecutive rays (rtcIntersect8 / rtcOccluded8) "
               "instead of one by one");
  app.add_flag(
      "--build-only", o.build_only,
      "time the builds (and the peer's), print the tree and its fingerprint; trace nothing");
  app.add_option("--settle-ms", o.settle_ms,
                 "build timings: sleep this long before each timed SAH and peer build and read "
                 "its CPU time this long after it, so each build's CPU time holds its own idle "
                 "workers' spin-waiting and none of earlier work's (0: back to back)")
      ->capture_default_str();
  if (const auto done = parse_command_line(app, argc, argv, common, comm.is_root())) return *done;
  RunReport report;
  report.app = "rtmini-bvh-bench";
  report.parameters = {{"mesh", o.mesh},
                       {"workload", o.workload},
                       {"quality", o.quality},
                       {"time_builds", o.time_builds},
                       {"copies", o.copies},
                       {"repeats", o.repeats},
                       {"camera", o.camera},
                       {"gpu_trace", o.gpu_trace},
                       {"ray_order", o.ray_order},
                       {"packets", o.packets},
                       {"peer_packets", o.peer_packets},
                       {"write_workload", o.write_workload},
                       {"seed", o.seed},
                       {"spatial_splits", o.spatial_splits},
                       {"split_budget", o.split_budget},
                       {"build_only", o.build_only},
                       {"settle_ms", o.settle_ms}};
  const int code = run(o, report, comm, common.memory_limit());
  // Phases only: the program has no dispatch loop of its own to record.
  if (!common.timings.empty())
    write_rank_timings(common.timings, comm, report.timer, RankTimings{},
                       {"rtmini-bvh-bench", "", o.mesh, report.parameters.dump(), {}});
  report.finish(comm, common.summary);
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  return rtmini::app_main("rtmini-bvh-bench", argc, argv, bench_main);
}
