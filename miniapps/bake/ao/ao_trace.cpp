#include "ao_trace.hpp"

#include <algorithm>
#include <functional>

#include "rtmini/geometry/offset.hpp"
#include "rtmini/parallel/spread_order.hpp"

namespace rtmini::ao {
namespace detail {

using DynamicPolicy = Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;

// Sample points, their normals and ray keys (one batch).
struct PointBatch {
  Kokkos::View<Vec3*, MemSpace> pos, nrm;
  Kokkos::View<std::uint32_t*, MemSpace> keys;
};

// Counts occluded rays k in [k0, k1) for each point at positions [begin, end) of `order`,
// added into hits.
void trace_pass(const OcclusionQuery& query, const PointBatch& points,
                const Kokkos::View<std::uint16_t*, MemSpace>& hits, std::int64_t begin,
                std::int64_t end, int k0, int k1, const TraceSettings& s,
                const SpreadOrder& order) {
  const auto pos = points.pos;
  const auto nrm = points.nrm;
  const auto keys = points.keys;
  const std::uint64_t seed = s.seed;
  const int side = stratum_side(s.rays);
  const Real offset = s.offset, max_distance = s.max_distance;
  const Real coordinate_bound = s.coordinate_bound;
  Kokkos::parallel_for(
      "rtmini::bake::ao::trace", DynamicPolicy(begin, end), KOKKOS_LAMBDA(std::int64_t at) {
        const std::int64_t i = order.item(at);
        const Vec3 normal = nrm(i);
        if (length_squared(normal) == Real(0)) return;  // degenerate triangle: zero weight later
        const Frame frame(normal);
        const std::uint32_t key = keys(i);
        Ray ray;
        ray.org = offset_ray_origin(pos(i), normal, coordinate_bound) + normal * offset;
        ray.tmin = Real(0);
        ray.tmax = max_distance;
        int count = 0;
        for (int k = k0; k < k1; ++k) {
          ray.dir = frame.to_world(ray_direction(seed, key, k, side));
          count += query.occluded(ray) ? 1 : 0;
        }
        hits(i) = static_cast<std::uint16_t>(hits(i) + count);
      });
}

// Points per dispatch at least, when a progress line splits a pass (TimedChunks).
constexpr std::int64_t kMinDispatchPoints = 4096;
// Consecutive points kept together by the spread order (a few neighbouring triangles' samples,
// whose rays share BVH nodes).
constexpr std::int64_t kSpreadBlockPoints = 256;

// With a progress line (`line` drawn, `after_dispatch` set) each pass is split into time-sized
// dispatches, so a long pass shows its progress, over the points in a spread order (each dispatch
// a sample of the whole batch: the rate so far holds for the rest, whatever part of the mesh is
// cheap to trace); a point's count is an integer sum over its rays, so the counts are the same
// for any split and order.
void trace_all_passes(const OcclusionQuery& query, const PointBatch& points,
                      const Kokkos::View<std::uint16_t*, MemSpace>& hits, std::int64_t n,
                      const TraceSettings& s, const ProgressLine* line = nullptr,
                      const std::function<void(std::int64_t rays)>& after_dispatch = nullptr) {
  Kokkos::deep_copy(hits, std::uint16_t(0));
  for (int p = 0; p < s.passes; ++p) {
    const int k0 = static_cast<int>(static_cast<std::int64_t>(s.rays) * p / s.passes);
    const int k1 = static_cast<int>(static_cast<std::int64_t>(s.rays) * (p + 1) / s.passes);
    std::int64_t begin = 0, end = 0;
    TimedChunks chunks(n, after_dispatch ? line : nullptr, kMinDispatchPoints);
    const SpreadOrder order = after_dispatch ? SpreadOrder(n, kSpreadBlockPoints) : SpreadOrder();
    while (chunks.next(begin, end)) {
      trace_pass(query, points, hits, begin, end, k0, k1, s, order);
      if (after_dispatch) after_dispatch((end - begin) * (k1 - k0));
    }
  }
}

// Rank-local progress of the ray passes, reported after every dispatch (a pass is split into
// several when a line is drawn). The rays traced are both what is shown and the cost.
class PassProgress {
 public:
  PassProgress(ProgressLine* line, const TraceSettings& s, std::int64_t points)
      : line_(line && line->enabled() ? line : nullptr),
        total_rays_(static_cast<double>(points) * s.rays) {}

  ProgressLine* line() const { return line_; }
  // Null when no line is drawn, so an unwatched run keeps its kernels unfenced.
  std::function<void(std::int64_t)> callback() {
    if (!line_) return nullptr;
    return [this](std::int64_t rays) {
      Kokkos::fence();  // a dispatch counts as done once it has run, not once it is queued
      rays_ += static_cast<double>(rays);
      line_->update(rays_, total_rays_);
    };
  }
  void finish() {
    if (line_) line_->finish(rays_, total_rays_);
  }

 private:
  ProgressLine* line_;
  double total_rays_, rays_ = 0;
};

// A receiver as the expansion kernel sees it: where its world triangles go and where its
// stored mesh lies in StoredMeshes' arrays.
struct ExpandReceiver {
  AffineD xform;                    // object -> world, in double as on the host
  std::int64_t tri_base = 0;        // its first global triangle
  std::int64_t mesh_tri_base = 0;   // its mesh's first triangle in StoredMeshes::corners / 3
  std::int64_t mesh_vert_base = 0;  // its mesh's first vertex in StoredMeshes::positions
  int mesh = 0;                     // stored mesh id (sample_item)
  std::uint32_t key = 0;            // instance id (ray key)
};

Kokkos::View<ExpandReceiver*, MemSpace> upload_receiver_table(const StoredMeshes& meshes,
                                                              const AoScene& scene,
                                                              const SamplePlan& plan) {
  const std::size_t nr = plan.receivers.size();
  std::vector<ExpandReceiver> table(nr);
  for (std::size_t r = 0; r < nr; ++r) {
    const int m = plan.meshes[r];
    table[r].xform = scene.instances[plan.receivers[r]].xform;
    table[r].tri_base = plan.tri_base[r];
    table[r].mesh_tri_base = meshes.tri_base[m];
    table[r].mesh_vert_base = meshes.vertex_base[m];
    table[r].mesh = m;
    table[r].key = static_cast<std::uint32_t>(plan.receivers[r]);
  }
  Kokkos::View<ExpandReceiver*, MemSpace> d(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::expand_receivers"), nr);
  Kokkos::deep_copy(d, compat::host_view(table.data(), nr));
  return d;
}

// AffineD::point with every product rounded on its own: CUDA would fuse them into
// multiply-adds, the host (-ffp-contract=off) does not, so this gives the host's bits in a
// kernel. Same order: ((m0 x + m1 y) + m2 z) + t.
KOKKOS_INLINE_FUNCTION Vec3d point_unfused(const AffineD& a, const Vec3d& p) {
  using rtmini::detail::mul_rn;
  const auto& m = a.m;
  return {mul_rn(m[0][0], p.x) + mul_rn(m[0][1], p.y) + mul_rn(m[0][2], p.z) + m[0][3],
          mul_rn(m[1][0], p.x) + mul_rn(m[1][1], p.y) + mul_rn(m[1][2], p.z) + m[1][3],
          mul_rn(m[2][0], p.x) + mul_rn(m[2][1], p.y) + mul_rn(m[2][2], p.z) + m[2][3]};
}

// Global triangle g of receiver r: its stored triangle g - tri_base[r] moved to the world in
// double and rounded to Real, its random-number item and its ray key. The world triangles
// are formed here instead of on the host, so only the stored meshes cross to the device.
void expand_receivers(const DeviceSamplePlan& d, const StoredMeshes& meshes,
                      const Kokkos::View<ExpandReceiver*, MemSpace>& receiver_table) {
  const auto receivers = receiver_table;
  const auto tris = d.tris;
  const auto items = d.items;
  const auto keys = d.ray_keys;
  const auto positions = meshes.positions;
  const auto corners = meshes.corners;
  const auto nr = static_cast<std::int64_t>(receivers.extent(0));
  Kokkos::parallel_for(
      "rtmini::bake::ao::expand_receivers",
      Kokkos::RangePolicy<ExecSpace>(0, static_cast<std::int64_t>(tris.extent(0))),
      KOKKOS_LAMBDA(std::int64_t g) {
        std::int64_t lo = 0, hi = nr;  // last receiver with tri_base <= g (skips empty ones)
        while (hi - lo > 1) {
          const std::int64_t mid = (lo + hi) / 2;
          if (receivers(mid).tri_base <= g)
            lo = mid;
          else
            hi = mid;
        }
        const ExpandReceiver& r = receivers(lo);
        const std::int64_t t = g - r.tri_base;
        const std::int64_t c = 3 * (r.mesh_tri_base + t);
        tris(g) = {Vec3(point_unfused(r.xform, positions(r.mesh_vert_base + corners(c)))),
                   Vec3(point_unfused(r.xform, positions(r.mesh_vert_base + corners(c + 1)))),
                   Vec3(point_unfused(r.xform, positions(r.mesh_vert_base + corners(c + 2))))};
        items(g) = sample_item(r.mesh, t);
        keys(g) = r.key;
      });
  // Done before the upload's phase ends (the console splits "Build BVHs" there), not in the
  // first sample kernel's time.
  ExecSpace().fence();
}

}  // namespace detail

int stratum_side(int rays) {
  int side = 0;
  while ((side + 1) * (side + 1) <= rays) ++side;
  return side;
}

DeviceSamplePlan upload_plan(const StoredMeshes& meshes, const AoScene& scene,
                             const SamplePlan& plan) {
  const std::int64_t triangles = plan.total_triangles();
  DeviceSamplePlan d;
  // Every element is written below (expansion kernel, copies): no zero fill first.
  d.tris = Kokkos::View<Triangle*, MemSpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::receiver_tris"),
      triangles);
  d.items = Kokkos::View<std::uint64_t*, MemSpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::sample_items"), triangles);
  d.ray_keys = Kokkos::View<std::uint32_t*, MemSpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::ray_keys"), triangles);
  d.offsets = Kokkos::View<std::int64_t*, MemSpace>(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::sample_offsets"),
      plan.offsets.size());
  // Straight from the vectors: one copy each, no host mirror to allocate and fill.
  Kokkos::deep_copy(d.offsets, compat::host_view(plan.offsets.data(), plan.offsets.size()));
  detail::expand_receivers(d, meshes, detail::upload_receiver_table(meshes, scene, plan));
  return d;
}

DeviceSamplePlan upload_plan(const AoScene& scene, const SamplePlan& plan) {
  return upload_plan(upload_meshes(scene), scene, plan);
}

std::vector<std::uint16_t> trace_samples(const OcclusionQuery& query, const DeviceSamplePlan& plan,
                                         const TraceSettings& s, std::int64_t first,
                                         std::int64_t last, PhaseTimer& timer,
                                         ProgressLine* progress) {
  std::vector<std::uint16_t> out(static_cast<std::size_t>(std::max<std::int64_t>(0, last - first)));
  const std::int64_t cap = std::min<std::int64_t>(s.batch, std::max<std::int64_t>(1, last - first));
  const detail::PointBatch batch{
      Kokkos::View<Vec3*, MemSpace>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::points"), cap),
      Kokkos::View<Vec3*, MemSpace>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::normals"), cap),
      Kokkos::View<std::uint32_t*, MemSpace>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::point_keys"), cap)};
  const auto pos = batch.pos;
  const auto nrm = batch.nrm;
  const auto point_keys = batch.keys;
  Kokkos::View<std::uint16_t*, MemSpace> hits("rtmini::bake::ao::hits", cap);
  auto hits_h = Kokkos::create_mirror_view(hits);
  const auto tris = plan.tris;
  const auto items = plan.items;
  const auto ray_keys = plan.ray_keys;
  const auto offsets = plan.offsets;
  const std::int64_t num_tris = static_cast<std::int64_t>(tris.extent(0));
  const std::uint64_t seed = s.seed;
  detail::PassProgress pass_progress(progress, s, last - first);
  const auto after_pass = pass_progress.callback();
  for (std::int64_t b0 = first; b0 < last; b0 += cap) {
    const std::int64_t n = std::min(cap, last - b0);
    timer.start("samples");
    Kokkos::parallel_for(
        "rtmini::bake::ao::sample_points", Kokkos::RangePolicy<ExecSpace>(0, n),
        KOKKOS_LAMBDA(std::int64_t i) {
          const std::int64_t id = b0 + i;
          std::int64_t lo = 0, hi = num_tris;  // last g with offsets(g) <= id
          while (hi - lo > 1) {
            const std::int64_t mid = (lo + hi) / 2;
            if (offsets(mid) <= id)
              lo = mid;
            else
              hi = mid;
          }
          const Triangle t = tris(lo);
          Real u, v;
          sample_barycentrics(seed, items(lo), id - offsets(lo), u, v);
          pos(i) = barycentric_point(t.a, t.b, t.c, u, v);
          nrm(i) = triangle_normal(t.a, t.b, t.c);
          point_keys(i) = ray_keys(lo);
        });
    timer.stop();
    timer.start("rays");
    detail::trace_all_passes(query, batch, hits, n, s, pass_progress.line(), after_pass);
    timer.stop();
    Kokkos::deep_copy(hits_h, hits);
    std::copy(hits_h.data(), hits_h.data() + n, out.begin() + (b0 - first));
  }
  pass_progress.finish();
  return out;
}

std::vector<std::uint16_t> trace_points(const OcclusionQuery& query,
                                        const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& normals, const TraceSettings& s,
                                        const std::vector<std::uint32_t>& keys) {
  const std::int64_t n = static_cast<std::int64_t>(points.size());
  const detail::PointBatch batch{
      Kokkos::View<Vec3*, MemSpace>("rtmini::bake::ao::probe_points", n),
      Kokkos::View<Vec3*, MemSpace>("rtmini::bake::ao::probe_normals", n),
      Kokkos::View<std::uint32_t*, MemSpace>("rtmini::bake::ao::probe_keys", n)};
  Kokkos::View<std::uint16_t*, MemSpace> hits("rtmini::bake::ao::probe_hits", n);
  auto ph = Kokkos::create_mirror_view(batch.pos);
  auto nh = Kokkos::create_mirror_view(batch.nrm);
  auto kh = Kokkos::create_mirror_view(batch.keys);
  for (std::int64_t i = 0; i < n; ++i) {
    ph(i) = points[i];
    nh(i) = normals[i];
    kh(i) = keys.empty() ? 0u : keys[i];
  }
  Kokkos::deep_copy(batch.pos, ph);
  Kokkos::deep_copy(batch.nrm, nh);
  Kokkos::deep_copy(batch.keys, kh);
  detail::trace_all_passes(query, batch, hits, n, s);
  auto hh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), hits);
  return std::vector<std::uint16_t>(hh.data(), hh.data() + n);
}

}  // namespace rtmini::ao
