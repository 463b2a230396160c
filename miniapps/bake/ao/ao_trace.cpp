#include "ao_trace.hpp"

#include <algorithm>
#include <functional>

#include "rtmini/geometry/offset.hpp"

namespace rtmini::ao {
namespace detail {

using DynamicPolicy = Kokkos::RangePolicy<ExecSpace, Kokkos::Schedule<Kokkos::Dynamic>>;

// Counts occluded rays k in [k0, k1) for each point in [begin, end), added into hits.
void trace_pass(const OcclusionQuery& query, const Kokkos::View<Vec3*, MemSpace>& pos,
                const Kokkos::View<Vec3*, MemSpace>& nrm, const Kokkos::View<Vec3*, MemSpace>& dirs,
                const Kokkos::View<std::uint16_t*, MemSpace>& hits, std::int64_t begin,
                std::int64_t end, int k0, int k1, Real offset, Real max_distance,
                Real coordinate_bound) {
  Kokkos::parallel_for(
      "rtmini::bake::ao::trace", DynamicPolicy(begin, end), KOKKOS_LAMBDA(std::int64_t i) {
        const Vec3 normal = nrm(i);
        if (length_squared(normal) == Real(0)) return;  // degenerate triangle: zero weight later
        const Frame frame(normal);
        Ray ray;
        ray.org = offset_ray_origin(pos(i), normal, coordinate_bound) + normal * offset;
        ray.tmin = Real(0);
        ray.tmax = max_distance;
        int count = 0;
        for (int k = k0; k < k1; ++k) {
          ray.dir = frame.to_world(dirs(k));
          count += query.occluded(ray) ? 1 : 0;
        }
        hits(i) = static_cast<std::uint16_t>(hits(i) + count);
      });
}

Kokkos::View<Vec3*, MemSpace> upload_directions(int rays, std::uint64_t seed) {
  const std::vector<Vec3> table = direction_table(rays, seed);
  Kokkos::View<Vec3*, MemSpace> dirs("rtmini::bake::ao::directions", table.size());
  auto h = Kokkos::create_mirror_view(dirs);
  for (std::size_t k = 0; k < table.size(); ++k) h(k) = table[k];
  Kokkos::deep_copy(dirs, h);
  return dirs;
}

// Points per dispatch at least, when a progress line splits a pass (TimedChunks).
constexpr std::int64_t kMinDispatchPoints = 4096;

// With a progress line (`line` drawn, `after_dispatch` set) each pass is split into time-sized
// dispatches, so a long pass shows its progress; a point's count is an integer sum over its rays,
// so the counts are the same for any split.
void trace_all_passes(const OcclusionQuery& query, const Kokkos::View<Vec3*, MemSpace>& pos,
                      const Kokkos::View<Vec3*, MemSpace>& nrm,
                      const Kokkos::View<Vec3*, MemSpace>& dirs,
                      const Kokkos::View<std::uint16_t*, MemSpace>& hits, std::int64_t n,
                      const TraceSettings& s, const ProgressLine* line = nullptr,
                      const std::function<void(std::int64_t rays)>& after_dispatch = nullptr) {
  Kokkos::deep_copy(hits, std::uint16_t(0));
  for (int p = 0; p < s.passes; ++p) {
    const int k0 = static_cast<int>(static_cast<std::int64_t>(s.rays) * p / s.passes);
    const int k1 = static_cast<int>(static_cast<std::int64_t>(s.rays) * (p + 1) / s.passes);
    std::int64_t begin = 0, end = 0;
    TimedChunks chunks(n, after_dispatch ? line : nullptr, kMinDispatchPoints);
    while (chunks.next(begin, end)) {
      trace_pass(query, pos, nrm, dirs, hits, begin, end, k0, k1, s.offset, s.max_distance,
                 s.coordinate_bound);
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

}  // namespace detail

std::vector<Vec3> direction_table(int rays, std::uint64_t seed) {
  int side = 0;
  while ((side + 1) * (side + 1) <= rays) ++side;
  std::vector<Vec3> out(static_cast<std::size_t>(rays));
  for (int k = 0; k < rays; ++k) {
    float jx, jy;
    Rng(seed, static_cast<std::uint64_t>(k), 1u).uniform2(0, jx, jy);
    Real u1 = jx, u2 = jy;
    if (k < side * side) stratified_2d(k, side, Real(jx), Real(jy), u1, u2);
    out[k] = cosine_hemisphere(u1, u2);
  }
  return out;
}

DeviceSamplePlan upload_plan(const AoScene& scene, const SamplePlan& plan) {
  DeviceSamplePlan d;
  d.tris =
      Kokkos::View<Triangle*, MemSpace>("rtmini::bake::ao::receiver_tris", plan.total_triangles());
  d.offsets = Kokkos::View<std::int64_t*, MemSpace>("rtmini::bake::ao::sample_offsets",
                                                    plan.offsets.size());
  d.items = Kokkos::View<std::uint64_t*, MemSpace>("rtmini::bake::ao::sample_items",
                                                   plan.total_triangles());
  auto th = Kokkos::create_mirror_view(d.tris);
  auto ih = Kokkos::create_mirror_view(d.items);
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoInstance& inst = scene.instances[plan.receivers[r]];
    const AoMesh& mesh = scene.meshes[inst.mesh];
    for (std::int64_t g = plan.tri_base[r]; g < plan.tri_base[r + 1]; ++g) {
      const auto& t = mesh.tris[g - plan.tri_base[r]];
      th(g) = {Vec3(inst.xform.point(mesh.positions[t[0]])),
               Vec3(inst.xform.point(mesh.positions[t[1]])),
               Vec3(inst.xform.point(mesh.positions[t[2]]))};
      ih(g) = plan.item(r, g);
    }
  }
  Kokkos::deep_copy(d.tris, th);
  Kokkos::deep_copy(d.items, ih);
  auto oh = Kokkos::create_mirror_view(d.offsets);
  std::copy(plan.offsets.begin(), plan.offsets.end(), oh.data());
  Kokkos::deep_copy(d.offsets, oh);
  return d;
}

std::vector<std::uint16_t> trace_samples(const OcclusionQuery& query, const DeviceSamplePlan& plan,
                                         const TraceSettings& s, std::int64_t first,
                                         std::int64_t last, PhaseTimer& timer,
                                         ProgressLine* progress) {
  std::vector<std::uint16_t> out(static_cast<std::size_t>(std::max<std::int64_t>(0, last - first)));
  const std::int64_t cap = std::min<std::int64_t>(s.batch, std::max<std::int64_t>(1, last - first));
  Kokkos::View<Vec3*, MemSpace> pos(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::points"), cap);
  Kokkos::View<Vec3*, MemSpace> nrm(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::ao::normals"), cap);
  Kokkos::View<std::uint16_t*, MemSpace> hits("rtmini::bake::ao::hits", cap);
  auto hits_h = Kokkos::create_mirror_view(hits);
  const auto dirs = detail::upload_directions(s.rays, s.seed);
  const auto tris = plan.tris;
  const auto items = plan.items;
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
        });
    timer.stop();
    timer.start("rays");
    detail::trace_all_passes(query, pos, nrm, dirs, hits, n, s, pass_progress.line(), after_pass);
    timer.stop();
    Kokkos::deep_copy(hits_h, hits);
    std::copy(hits_h.data(), hits_h.data() + n, out.begin() + (b0 - first));
  }
  pass_progress.finish();
  return out;
}

std::vector<std::uint16_t> trace_points(const OcclusionQuery& query,
                                        const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& normals, const TraceSettings& s) {
  const std::int64_t n = static_cast<std::int64_t>(points.size());
  Kokkos::View<Vec3*, MemSpace> pos("rtmini::bake::ao::probe_points", n),
      nrm("rtmini::bake::ao::probe_normals", n);
  Kokkos::View<std::uint16_t*, MemSpace> hits("rtmini::bake::ao::probe_hits", n);
  auto ph = Kokkos::create_mirror_view(pos);
  auto nh = Kokkos::create_mirror_view(nrm);
  for (std::int64_t i = 0; i < n; ++i) {
    ph(i) = points[i];
    nh(i) = normals[i];
  }
  Kokkos::deep_copy(pos, ph);
  Kokkos::deep_copy(nrm, nh);
  detail::trace_all_passes(query, pos, nrm, detail::upload_directions(s.rays, s.seed), hits, n, s);
  auto hh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), hits);
  return std::vector<std::uint16_t>(hh.data(), hh.data() + n);
}

}  // namespace rtmini::ao
