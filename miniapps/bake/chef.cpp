#include "chef.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "map_reader.hpp"
#include "reference_tracer.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/geometry/offset.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini::bake {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Bvh = bvh::Bvh<MemSpace>;

// The viewpoint directions of the map (HemisphereMap, map_reader.hpp): the N shared points, in
// each vertex's frame when the map stores the front hemisphere only (Chef::hemisphere_map adds
// the lookup's structure over the stored half and its images).
HemisphereMap hemisphere_map(const BakeSceneDevice& s, const BakeConfig& c) {
  return {s.normal, s.viewpoints, c.hemisphere() ? c.stored_viewpoints() : 0, {}, {}};
}

// Rng sample-index streams: shadow samples use [0, S); gather rays start here.
constexpr std::uint32_t kGatherStream = 1u << 24;

struct DirectLight {
  Bvh accel;
  Kokkos::View<Vec3*, MemSpace> positions, normal, diffuse, emissive, base;
  Kokkos::View<Triangle*, MemSpace> tris;
  Kokkos::View<AreaLight*, MemSpace> lights;
  std::int64_t begin;
  int samples;
  std::uint64_t seed;
  Real coordinate_bound = 0;  // DeviceMesh::coordinate_bound, for offset_ray_origin

  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t v, std::int64_t& rays) const {
    Vec3 c = emissive(v);
    const Vec3 n = normal(v), kd = diffuse(v);
    if (max_component(kd) > Real(0) && length_squared(n) > Real(0)) {
      const Vec3 p = positions(v);
      const Vec3 org = offset_ray_origin(p, n, coordinate_bound);
      const int grid = static_cast<int>(math::sqrt(Real(samples)) + Real(1e-3));
      Vec3 irradiance(Real(0));
      for (int l = 0; l < static_cast<int>(lights.extent(0)); ++l) {
        const AreaLight light = lights(l);
        Vec3 sum(Real(0));
        for (int s = 0; s < samples; ++s) {
          float u1, u2;
          Rng(seed, static_cast<std::uint64_t>(v), static_cast<std::uint32_t>(s))
              .uniform2(static_cast<std::uint32_t>(l), u1, u2);
          Real x = u1, y = u2;
          // Jittered strata for the first grid^2 samples, plain uniform for the rest.
          if (s < grid * grid) stratified_2d(s, grid, Real(u1), Real(u2), x, y);
          int t = light.tri[0];
          if (x < light.first_fraction) {
            x = x / light.first_fraction;
          } else {
            x = (x - light.first_fraction) / (Real(1) - light.first_fraction);
            t = light.tri[1];
          }
          x = math::fmin(x, Real(1) - Real(1e-7));
          Real bu, bv;
          uniform_triangle(x, y, bu, bv);
          const Triangle tri = tris(t);
          const Vec3 q = barycentric_point(tri.a, tri.b, tri.c, bu, bv);
          const Vec3 to = q - p;
          const Real d2 = length_squared(to);
          if (!(d2 > Real(0))) continue;
          const Vec3 wi = to * (Real(1) / math::sqrt(d2));
          const Real cos_p = dot(n, wi), cos_l = -dot(light.normal, wi);
          if (cos_p <= Real(0) || cos_l <= Real(0)) continue;
          const Vec3 target = offset_ray_origin(q, light.normal, coordinate_bound);
          const Vec3 seg = target - org;
          const Real len = length(seg);
          Ray ray;
          ray.org = org;
          ray.dir = seg * (Real(1) / len);
          // A vertex on an inside corner lies on the neighbouring wall's plane (its own faces
          // do not include that wall), so a ray leaving it would hit that wall at t = 0: skip
          // hits within a relative 1e-5 of the segment (leaks only through geometry that
          // close to the vertex).
          ray.tmin = len * Real(1e-5);
          ray.tmax = len;
          ++rays;
          if (!bvh::any_hit(accel, ray)) sum += light.emission * (cos_p * cos_l / d2);
        }
        irradiance += sum * (light.area / Real(samples));
      }
      c += kd * irradiance * Real(1.0 / math::kPi);
    }
    base(v) = c;
  }
};

template <class LookupT>
struct DiffuseGather {
  Bvh accel;
  MapReader<LookupT> reader;
  Kokkos::View<Vec3*, MemSpace> positions, normal, diffuse, gather;
  int rays_per_vertex, iteration;
  std::uint64_t seed;
  Real coordinate_bound = 0;  // DeviceMesh::coordinate_bound, for offset_ray_origin

  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t v, std::int64_t& rays) const {
    const Vec3 n = normal(v);
    Vec3 sum(Real(0));
    if (max_component(diffuse(v)) > Real(0) && length_squared(n) > Real(0)) {
      const Frame frame(n);
      Ray ray;
      ray.org = offset_ray_origin(positions(v), n, coordinate_bound);
      for (int j = 0; j < rays_per_vertex; ++j) {
        const std::uint32_t sample =
            kGatherStream + static_cast<std::uint32_t>((iteration - 1) * rays_per_vertex + j);
        float u1, u2;
        Rng(seed, static_cast<std::uint64_t>(v), sample).uniform2(0u, u1, u2);
        ray.dir = normalize(frame.to_world(cosine_hemisphere(Real(u1), Real(u2))));
        const Hit hit = bvh::closest_hit(accel, ray);
        ++rays;
        sum += reader.read(hit.prim, hit.u, hit.v, ray.dir, true);
      }
      // Cosine-weighted sampling: (1/M) sum L estimates the irradiance / pi.
      sum = sum * (Real(1) / Real(rays_per_vertex));
    }
    gather(v) = sum;
  }
};

// The vertex in [vbegin, vend) that owns colour item `item`: the last whose first item <= item.
template <class Offsets>
KOKKOS_INLINE_FUNCTION std::int64_t vertex_of_item(const Offsets& color_offset, std::int64_t vbegin,
                                                   std::int64_t vend, std::int64_t item) {
  std::int64_t lo = vbegin, hi = vend - 1;
  while (lo < hi) {
    const std::int64_t mid = (lo + hi + 1) / 2;
    if (color_offset(mid) <= item)
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

// The colour items [first, end) of vertices [begin, end) (one per viewpoint, one per
// view-independent vertex), read from the device offsets.
struct ItemRange {
  std::int64_t first = 0, end = 0;
};
inline ItemRange item_range(const Kokkos::View<std::int64_t*, MemSpace>& color_offset,
                            std::int64_t vbegin, std::int64_t vend) {
  ItemRange r;
  Kokkos::deep_copy(r.first, Kokkos::subview(color_offset, vbegin));
  Kokkos::deep_copy(r.end, Kokkos::subview(color_offset, vend));
  return r;
}

// Runs the functor over the items with dynamic scheduling (vertices differ in cost: mirror
// bounces, cache hits) and returns the rays it counted.
template <class Functor>
std::int64_t trace_items(const char* label, const ItemRange& items, const Functor& f) {
  std::int64_t rays = 0;
  Kokkos::parallel_reduce(
      label,
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>, Kokkos::Schedule<Kokkos::Dynamic>>(
          items.first, items.end),
      f, rays);
  return rays;
}

template <class LookupT>
struct MirrorIteration {
  Bvh accel;
  MapReader<LookupT> reader;
  Kokkos::View<Vec3*, MemSpace> positions, normal, diffuse, reflective, base, gather, views;
  Kokkos::View<int*, MemSpace> order;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;  // the map's offsets (MapLayout)
  Kokkos::View<CachedHit*, MemSpace> cache;
  Kokkos::View<TracedHit*, MemSpace> traced;
  Kokkos::View<Vec3f*, MemSpace> next;
  std::int64_t vbegin, vend, item_begin, cache_offset;
  int iteration;
  bool with_gather;
  HitCacheMode cache_mode;
  Real coordinate_bound = 0;  // DeviceMesh::coordinate_bound, for offset_ray_origin
  bool two_sided = false;     // BakeConfig::two_sided (mirror_normal)

  // n: the side the ray leaves from (mirror_normal).
  KOKKOS_INLINE_FUNCTION Hit mirror_hit(std::int64_t v, const Vec3& n, const Vec3& r,
                                        std::int64_t slot, std::int64_t& rays) const {
    Hit hit;
    if (cache_mode == HitCacheMode::kUse) {
      const CachedHit h = cache(slot);
      hit.prim = h.prim;
      hit.u = Real(h.u);
      hit.v = Real(h.v);
    } else if (cache_mode == HitCacheMode::kTraced) {
      const TracedHit h = traced(slot);
      hit.prim = h.prim;
      hit.u = h.u;
      hit.v = h.v;
    } else {
      Ray ray;
      ray.org = offset_ray_origin(positions(v), n, coordinate_bound);
      ray.dir = r;
      hit = bvh::closest_hit(accel, ray);
      ++rays;
      if (cache_mode == HitCacheMode::kFill) cache(slot) = cached_hit(hit);
    }
    return hit;
  }

  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t item, std::int64_t& rays) const {
    const std::int64_t v = vertex_of_item(color_offset, vbegin, vend, item);
    const std::int64_t first = color_offset(v);
    Vec3 c = base(v);
    if (with_gather) c += diffuse(v) * gather(v);
    if (iteration > 0 && color_offset(v + 1) - first > 1) {
      // An item is a storage slot (view_order.hpp): neighbouring items take neighbouring
      // directions, coherent traversal and lookups.
      const int view = order(item - first);
      const Vec3 d = reader.hemisphere.direction(v, view);
      const Vec3 n = mirror_normal(d, normal(v), two_sided);
      const Vec3 r = mirror_direction(d, n);
      const Hit hit = mirror_hit(v, n, r, cache_offset + (item - item_begin), rays);
      c += reflective(v) * reader.read(hit.prim, hit.u, hit.v, r);
    }
    next(item) = Vec3f(c);
  }
};

// The mirror rays of the view-dependent vertices of a batch, traced once (same directions,
// order and cache slots as MirrorIteration) into the traced hits.
struct TraceMirrorHits {
  Bvh accel;
  Kokkos::View<Vec3*, MemSpace> positions, normal, views;
  Kokkos::View<int*, MemSpace> order;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;
  Kokkos::View<TracedHit*, MemSpace> traced;
  std::int64_t vbegin, vend, item_begin, cache_offset;
  Real coordinate_bound;   // DeviceMesh::coordinate_bound, for offset_ray_origin
  bool two_sided = false;  // BakeConfig::two_sided (mirror_normal)
  HemisphereMap hemisphere{};

  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t item, std::int64_t& rays,
                                         std::int64_t& nodes) const {
    const std::int64_t v = vertex_of_item(color_offset, vbegin, vend, item);
    const std::int64_t first = color_offset(v);
    const std::int64_t slot = cache_offset + (item - item_begin);
    TracedHit t;
    if (color_offset(v + 1) - first > 1) {
      const Vec3 d = hemisphere.direction(v, order(item - first));
      const Vec3 n = mirror_normal(d, normal(v), two_sided);
      Ray ray;
      ray.org = offset_ray_origin(positions(v), n, coordinate_bound);
      ray.dir = mirror_direction(d, n);
      bvh::TraversalStats stats;  // the same hit as without; the nodes measure the trace's work
      const Hit hit = bvh::closest_hit(accel, ray, stats);
      ++rays;
      nodes += stats.nodes;
      t.prim = hit.prim;
      t.u = hit.u;
      t.v = hit.v;
    }
    traced(slot) = t;
  }
};

struct TraceReference {
  ReferenceTracer tracer;
  Kokkos::View<std::int64_t*, MemSpace> color_offset;  // the output's offsets (MapLayout)
  Kokkos::View<Vec3*, MemSpace> views;
  Kokkos::View<int*, MemSpace> order;  // slot -> viewpoint (view_order.hpp)
  Kokkos::View<Vec3f*, MemSpace> out;
  std::int64_t vbegin, vend;
  int iterations;

  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t item, std::int64_t& rays) const {
    const std::int64_t v = vertex_of_item(color_offset, vbegin, vend, item);
    const std::int64_t first = color_offset(v);
    const int view = color_offset(v + 1) - first > 1 ? order(item - first) : 0;
    out(item) = Vec3f(tracer.radiance(static_cast<int>(v), views(view), iterations, rays));
  }
};

}  // namespace

MirrorCostEstimate estimate_mirror_costs(const BakeSceneDevice& scene, const BakeConfig& config,
                                         std::int64_t begin, std::int64_t end, int samples,
                                         std::int64_t& rays) {
  Kokkos::View<float*, MemSpace> hits("rtmini::bake::pilot_hits", end - begin);
  Kokkos::View<float*, MemSpace> nodes("rtmini::bake::pilot_nodes", end - begin);
  const Bvh accel = scene.mesh.accel;
  const auto positions = scene.mesh.positions;
  const auto normal = scene.normal;
  const HemisphereMap hemisphere = hemisphere_map(scene, config);
  const auto color_offset = scene.color_offset;
  const auto tri_vertices = scene.mesh.tri_vertices;
  const Real bound = scene.mesh.coordinate_bound;
  const int n = config.stored_viewpoints();
  const bool two_sided = config.two_sided;
  std::int64_t traced = 0;
  Kokkos::parallel_reduce(
      "rtmini::bake::pilot_mirror_costs",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>, Kokkos::Schedule<Kokkos::Dynamic>>(
          begin, end),
      KOKKOS_LAMBDA(std::int64_t v, std::int64_t & count) {
        if (color_offset(v + 1) - color_offset(v) <= 1) return;
        Ray ray;
        int hit = 0;
        bvh::TraversalStats stats;
        for (int s = 0; s < samples; ++s) {
          // Fibonacci points are ordered by height: every n/samples-th spans the sphere.
          const int view =
              static_cast<int>((2 * s + 1) * static_cast<std::int64_t>(n) / (2 * samples));
          const Vec3 d = hemisphere.direction(v, view);
          const Vec3 m = mirror_normal(d, normal(v), two_sided);
          ray.org = offset_ray_origin(positions(v), m, bound);
          ray.dir = mirror_direction(d, m);
          const int prim = bvh::closest_hit(accel, ray, stats).prim;
          if (prim < 0) continue;
          // Only a view-dependent vertex of the hit triangle costs a viewpoint lookup.
          bool lookup = false;
          for (int k = 0; k < 3; ++k) {
            const int q = tri_vertices(prim, k);
            lookup = lookup || color_offset(q + 1) - color_offset(q) > 1;
          }
          hit += lookup ? 1 : 0;
        }
        count += samples;
        const float scale = static_cast<float>(n) / static_cast<float>(samples);
        hits(v - begin) = scale * static_cast<float>(hit);
        nodes(v - begin) = scale * static_cast<float>(stats.nodes);
      },
      traced);
  rays += traced;
  MirrorCostEstimate out;
  compat::download(hits, out.lookup_hits);
  compat::download(nodes, out.nodes);
  return out;
}

Chef::Chef(const BakeSceneDevice& scene, const BakeConfig& config, std::int64_t local_items)
    : scene_(scene),
      config_(config),
      map_offset_(scene.color_offset),
      local_items_(local_items),
      caches_hits_(config.cache_hits && config.iterations > 1) {
  const std::size_t nv = scene.normal.extent(0);
  base_ = Kokkos::View<Vec3*, MemSpace>("rtmini::bake::base", nv);
  if (config.gather_rays > 0) gather_ = Kokkos::View<Vec3*, MemSpace>("rtmini::bake::gather", nv);
  view_order_ = coherent_view_order(config.viewpoints, config.stored_viewpoints());
  order_.view = compat::upload<MemSpace>("rtmini::bake::view_of_slot", view_order_.order);
  order_.slot = compat::upload<MemSpace>("rtmini::bake::slot_of_view", view_order_.slot);
  if (config.lookup == Lookup::kGrid) {
    grid_ = build_fibonacci_grid<MemSpace>(config.viewpoints);
    if (config.hemisphere()) mirrored_grid_ = build_mirrored_grid<MemSpace>(config.viewpoints);
  } else if (config.lookup == Lookup::kKdTree) {
    kdtree_ = build_fibonacci_kdtree<MemSpace>(config.viewpoints);
    if (config.hemisphere()) mirrored_ = build_mirrored_kdtree<MemSpace>(config.viewpoints);
  } else
    inverse_ = build_fibonacci_inverse<MemSpace>(config.viewpoints);
}

HemisphereMap Chef::hemisphere_map() const {
  HemisphereMap h = bake::hemisphere_map(scene_, config_);
  h.mirrored = mirrored_;
  h.mirrored_grid = mirrored_grid_;
  return h;
}

std::int64_t Chef::bake_base(std::int64_t begin, std::int64_t end) {
  DirectLight k{scene_.mesh.accel,      scene_.mesh.positions, scene_.normal,
                scene_.diffuse,         scene_.emissive,       base_,
                scene_.mesh.tris,       scene_.lights,         begin,
                config_.shadow_samples, config_.seed,          scene_.mesh.coordinate_bound};
  std::int64_t rays = 0;
  Kokkos::parallel_reduce("rtmini::bake::direct_light",
                          Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(begin, end), k,
                          rays);
  return rays;
}

std::int64_t Chef::trace_reference(std::int64_t begin, std::int64_t end,
                                   Kokkos::View<Vec3f*, MemSpace> out) {
  ReferenceTracer tracer{scene_.mesh.accel,
                         scene_.mesh.tri_vertices,
                         scene_.color_offset,
                         scene_.mesh.positions,
                         scene_.normal,
                         scene_.reflective,
                         base_,
                         Vec3(config_.background),
                         scene_.mesh.coordinate_bound};
  tracer.two_sided = config_.two_sided;
  const TraceReference k{tracer, map_offset_, scene_.viewpoints, order_.view, out,
                         begin,  end,         config_.iterations};
  return trace_items("rtmini::bake::trace_reference", item_range(map_offset_, begin, end), k);
}

ReadCount Chef::trace_mirror_hits(std::int64_t begin, std::int64_t end, std::int64_t cache_offset) {
  if (traced_.extent(0) == 0)
    traced_ = Kokkos::View<TracedHit*, MemSpace>("rtmini::bake::traced_hits", local_items_);
  return trace_mirror_hits_into(traced_, begin, end, cache_offset);
}

ReadCount Chef::trace_mirror_hits_into(Kokkos::View<TracedHit*, MemSpace> traced,
                                       std::int64_t begin, std::int64_t end,
                                       std::int64_t cache_offset) const {
  const ItemRange items = item_range(scene_.color_offset, begin, end);
  TraceMirrorHits k{scene_.mesh.accel,
                    scene_.mesh.positions,
                    scene_.normal,
                    scene_.viewpoints,
                    order_.view,
                    scene_.color_offset,
                    traced,
                    begin,
                    end,
                    items.first,
                    cache_offset,
                    scene_.mesh.coordinate_bound};
  k.two_sided = config_.two_sided;
  k.hemisphere = hemisphere_map();
  ReadCount count;
  Kokkos::parallel_reduce(
      "rtmini::bake::trace_mirror_hits",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>, Kokkos::Schedule<Kokkos::Dynamic>>(
          items.first, items.end),
      KOKKOS_LAMBDA(std::int64_t item, std::int64_t & rays, std::int64_t & nodes) {
        k(item, rays, nodes);
      },
      count.rays, count.nodes);
  return count;
}

ReadCount Chef::count_mirror_reads(std::int64_t begin, std::int64_t end, std::int64_t cache_offset,
                                   Kokkos::View<const char*, MemSpace> owned,
                                   Kokkos::View<char*, MemSpace> read) const {
  const ItemRange items = item_range(scene_.color_offset, begin, end);
  // Which vertices the hits read (flags: any rank writing 1 is enough), and how many are remote.
  auto traced = traced_;
  auto tri_vertices = scene_.mesh.tri_vertices;
  auto color_offset = scene_.color_offset;
  const std::int64_t first_slot = cache_offset;
  std::int64_t lookups = 0, reads = 0, view_reads = 0, remote = 0;
  Kokkos::parallel_reduce(
      "rtmini::bake::mark_read_vertices",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(0, items.end - items.first),
      KOKKOS_LAMBDA(std::int64_t i, std::int64_t & l, std::int64_t & n, std::int64_t & vd,
                    std::int64_t & r) {
        const int prim = traced(first_slot + i).prim;
        if (prim < 0) return;
        bool lookup = false;
        for (int k3 = 0; k3 < 3; ++k3) {
          const int vert = tri_vertices(prim, k3);
          const bool dependent = color_offset(vert + 1) - color_offset(vert) > 1;
          read(vert) = 1;
          n += 1;
          vd += dependent ? 1 : 0;
          lookup = lookup || dependent;
          if (!owned(vert)) r += 1;
        }
        l += lookup ? 1 : 0;
      },
      lookups, reads, view_reads, remote);
  ReadCount count;
  count.lookups = lookups;
  count.reads = reads;
  count.view_reads = view_reads;
  count.remote_reads = remote;
  return count;
}

std::vector<float> Chef::lookup_hits(std::int64_t begin, std::int64_t end,
                                     std::int64_t cache_offset) const {
  Kokkos::View<float*, MemSpace> hits("rtmini::bake::lookup_hits", end - begin);
  auto traced = traced_;
  auto tri_vertices = scene_.mesh.tri_vertices;
  auto color_offset = scene_.color_offset;
  std::int64_t vertex_begin_item = 0;
  Kokkos::deep_copy(vertex_begin_item, Kokkos::subview(color_offset, begin));
  const std::int64_t slot0 = cache_offset - vertex_begin_item;  // slot of global item g: slot0 + g
  Kokkos::parallel_for(
      "rtmini::bake::lookup_hits",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(begin, end),
      KOKKOS_LAMBDA(std::int64_t v) {
        if (color_offset(v + 1) - color_offset(v) <= 1) return;
        int count = 0;
        for (std::int64_t g = color_offset(v); g < color_offset(v + 1); ++g) {
          const int prim = traced(slot0 + g).prim;
          if (prim < 0) continue;
          bool lookup = false;
          for (int k = 0; k < 3; ++k) {
            const int q = tri_vertices(prim, k);
            lookup = lookup || color_offset(q + 1) - color_offset(q) > 1;
          }
          count += lookup ? 1 : 0;
        }
        hits(v - begin) = static_cast<float>(count);
      });
  std::vector<float> out;
  compat::download(hits, out);
  return out;
}

Kokkos::View<TracedHit*, MemSpace> Chef::take_traced_hits() {
  Kokkos::View<TracedHit*, MemSpace> out = traced_;
  traced_ = Kokkos::View<TracedHit*, MemSpace>();
  return out;
}

void Chef::adopt_traced_hits(Kokkos::View<TracedHit*, MemSpace> hits) {
  local_items_ = static_cast<std::int64_t>(hits.extent(0));
  traced_ = hits;
}

// The float hit cache made from the traced hits: the same view when the traced hits are float
// already, a narrowed copy otherwise (RTMINI_DOUBLE). Overloads rather than `if constexpr`, which
// discards the branch not taken only inside a template.
Kokkos::View<CachedHit*, MemSpace> hits_as_cache(Kokkos::View<CachedHit*, MemSpace> traced) {
  return traced;
}

template <class Traced>
Kokkos::View<CachedHit*, MemSpace> hits_as_cache(Kokkos::View<Traced*, MemSpace> traced) {
  Kokkos::View<CachedHit*, MemSpace> cache(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::hit_cache"), traced.extent(0));
  Kokkos::parallel_for(
      "rtmini::bake::fill_hit_cache",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(
          0, static_cast<std::int64_t>(traced.extent(0))),
      KOKKOS_LAMBDA(std::int64_t i) { cache(i) = cached_hit(traced(i)); });
  return cache;
}

void Chef::release_traced_hits() {
  if (!caches_hits_) return;  // the traced hits serve every iteration
  cache_ = hits_as_cache(traced_);
  traced_ = Kokkos::View<TracedHit*, MemSpace>();
}

namespace {
// The remote colours the lookups at a batch's traced hits read (see Chef::mark_read_items).
template <class LookupT>
struct MarkReadItems {
  LookupT lookup;
  Real radius;
  Kokkos::View<int* [3], MemSpace> tri_vertices;
  Kokkos::View<Vec3*, MemSpace> normal, views;
  Kokkos::View<int*, MemSpace> order;
  Kokkos::View<std::int64_t*, MemSpace> color_offset, map_offset;
  Kokkos::View<TracedHit*, MemSpace> traced;
  Kokkos::View<const char*, MemSpace> owned;
  Kokkos::View<char*, MemSpace> items;
  std::int64_t vbegin, vend, item_begin, cache_offset;
  bool two_sided = false;  // BakeConfig::two_sided (mirror_normal)
  HemisphereMap hemisphere{};
  Kokkos::View<const int*, MemSpace> slot{};  // viewpoint -> storage slot (to_slots)

  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t item) const {
    const int prim = traced(cache_offset + (item - item_begin)).prim;
    if (prim < 0) return;
    // Most hits read only owned vertices: they skip the vertex search and the direction (the
    // measured recut marks every kept item for the few vertices given away).
    if (owned(tri_vertices(prim, 0)) && owned(tri_vertices(prim, 1)) &&
        owned(tri_vertices(prim, 2)))
      return;
    const std::int64_t v = vertex_of_item(color_offset, vbegin, vend, item);
    const std::int64_t first = color_offset(v);
    if (color_offset(v + 1) - first <= 1) return;
    const Vec3 d = hemisphere.direction(v, order(item - first));
    const Vec3 r = mirror_direction(d, mirror_normal(d, normal(v), two_sided));
    ViewNeighbors nb;
    bool have_nb = false;
    for (int k = 0; k < 3; ++k) {
      const int vert = tri_vertices(prim, k);
      if (owned(vert)) continue;
      const std::int64_t at = map_offset(vert);
      if (color_offset(vert + 1) - color_offset(vert) == 1) {
        items(at) = 1;
        continue;
      }
      if (hemisphere.on()) {  // each vertex has its own frame
        nb = hemisphere.neighbors(lookup, vert, r, radius);
        to_slots(slot, nb);
      } else if (!have_nb) {
        nb = lookup.neighbors(r, radius);
        to_slots(slot, nb);
        have_nb = true;
      }
      for (int j = 0; j < nb.count; ++j) items(at + nb.index[j]) = 1;
    }
  }
};

template <class LookupT>
void mark_read_items_with(const LookupT& lookup, const BakeSceneDevice& s, const BakeConfig& cfg,
                          const StorageOrder& order,
                          Kokkos::View<std::int64_t*, MemSpace> map_offset,
                          Kokkos::View<TracedHit*, MemSpace> traced, std::int64_t begin,
                          std::int64_t end, std::int64_t cache_offset,
                          Kokkos::View<const char*, MemSpace> owned,
                          Kokkos::View<char*, MemSpace> items, const HemisphereMap& hemisphere) {
  const ItemRange r = item_range(s.color_offset, begin, end);
  MarkReadItems<LookupT> k{lookup,
                           fibonacci_radius(cfg.viewpoints),
                           s.mesh.tri_vertices,
                           s.normal,
                           s.viewpoints,
                           order.view,
                           s.color_offset,
                           map_offset,
                           traced,
                           owned,
                           items,
                           begin,
                           end,
                           r.first,
                           cache_offset};
  k.two_sided = cfg.two_sided;
  k.hemisphere = hemisphere;
  k.slot = order.slot;
  Kokkos::parallel_for("rtmini::bake::mark_read_items",
                       Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(r.first, r.end),
                       k);
}
}  // namespace

void Chef::mark_read_items(std::int64_t begin, std::int64_t end, std::int64_t cache_offset,
                           Kokkos::View<const char*, MemSpace> owned,
                           Kokkos::View<char*, MemSpace> items) const {
  const HemisphereMap hemisphere = hemisphere_map();
  with_lookup([&](const auto& lookup) {
    mark_read_items_with(lookup, scene_, config_, order_, map_offset_, traced_, begin, end,
                         cache_offset, owned, items, hemisphere);
  });
}

namespace {
// The map along reference entry e (vertex e / ref_n, direction e % ref_n), as MapReader reads
// one vertex: its single colour, or its viewpoints near the direction, weighted.
template <class LookupT>
struct MapAlong {
  LookupT lookup;
  Real radius;
  Kokkos::View<std::int64_t*, MemSpace> offset;
  Kokkos::View<const Vec3f*, MemSpace> map;
  int ref_n;
  HemisphereMap hemisphere{};

  KOKKOS_INLINE_FUNCTION Vec3 operator()(std::int64_t e, bool& view_dependent) const {
    const std::int64_t v = e / ref_n, first = offset(v);
    view_dependent = offset(v + 1) - first > 1;
    if (!view_dependent) return Vec3(map(first));
    const Vec3 dir = fibonacci_point(static_cast<int>(e % ref_n), ref_n);
    const ViewNeighbors nb = hemisphere.on() ? hemisphere.neighbors(lookup, v, dir, radius)
                                             : lookup.neighbors(dir, radius);
    Vec3 c(Real(0));
    for (int k = 0; k < nb.count; ++k) c += Vec3(map(first + nb.index[k])) * nb.weight[k];
    return c;
  }
};

template <class LookupT>
ErrorSums lookup_errors_with(const LookupT& lookup, Real radius,
                             Kokkos::View<std::int64_t*, MemSpace> offset,
                             Kokkos::View<const Vec3f*, MemSpace> map,
                             Kokkos::View<const Vec3f*, MemSpace> reference, int ref_n,
                             const HemisphereMap& hemisphere) {
  ErrorSums s;
  const std::int64_t entries = static_cast<std::int64_t>(reference.extent(0));
  s.entries = entries;
  using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>;
  const MapAlong<LookupT> read{lookup, radius, offset, map, ref_n, hemisphere};
  double vd_count = 0;
  Kokkos::parallel_reduce(
      "rtmini::bake::lookup_errors", Policy(0, entries),
      KOKKOS_LAMBDA(std::int64_t e, double& abs, double& sq, double& rel, double& ref,
                    double& vd_sq, double& vd) {
        bool dependent = false;
        const Vec3 a = read(e, dependent), b = Vec3(reference(e));
        const double da[3] = {double(a.x) - double(b.x), double(a.y) - double(b.y),
                              double(a.z) - double(b.z)};
        const double rb[3] = {double(b.x), double(b.y), double(b.z)};
        for (int c = 0; c < 3; ++c) {
          abs += da[c] < 0 ? -da[c] : da[c];
          sq += da[c] * da[c];
          rel += da[c] * da[c] / (rb[c] * rb[c] + 1e-2);
          ref += rb[c];
          if (dependent) vd_sq += da[c] * da[c];
        }
        if (dependent) vd += 1.0;
      },
      s.abs, s.sq, s.rel, s.ref, s.view_dependent_sq, vd_count);
  s.view_dependent = static_cast<std::int64_t>(vd_count);
  Kokkos::parallel_reduce(
      "rtmini::bake::lookup_errors_max", Policy(0, entries),
      KOKKOS_LAMBDA(std::int64_t e, double& m) {
        bool dependent = false;
        const Vec3 a = read(e, dependent), b = Vec3(reference(e));
        const double d[3] = {double(a.x) - double(b.x), double(a.y) - double(b.y),
                             double(a.z) - double(b.z)};
        for (int c = 0; c < 3; ++c) {
          const double ad = d[c] < 0 ? -d[c] : d[c];
          if (ad > m) m = ad;
        }
      },
      Kokkos::Max<double>(s.max_abs));
  return s;
}
}  // namespace

ErrorSums Chef::lookup_errors(Kokkos::View<const Vec3f*, MemSpace> map,
                              Kokkos::View<const Vec3f*, MemSpace> reference, int ref_n) const {
  const Real radius = fibonacci_radius(config_.viewpoints);
  const HemisphereMap hemisphere = hemisphere_map();
  return with_lookup([&](const auto& lookup) {
    return lookup_errors_with(lookup, radius, scene_.color_offset, map, reference, ref_n,
                              hemisphere);
  });
}

namespace {
template <class LookupT>
std::int64_t run_iteration(const BakeSceneDevice& s, const BakeConfig& cfg, const LookupT& lookup,
                           Kokkos::View<Vec3*, MemSpace> base, Kokkos::View<Vec3*, MemSpace> gather,
                           Kokkos::View<CachedHit*, MemSpace> cache,
                           Kokkos::View<TracedHit*, MemSpace> traced,
                           Kokkos::View<std::int64_t*, MemSpace> map_offset,
                           const SparseColors& sparse, const FirstReads& first_reads,
                           const StorageOrder& order, int it, std::int64_t begin, std::int64_t end,
                           std::int64_t cache_offset, HitCacheMode mode,
                           Kokkos::View<const Vec3f*, MemSpace> prev,
                           Kokkos::View<Vec3f*, MemSpace> next, const HemisphereMap& hemisphere) {
  const Vec3f bg = cfg.background;
  // With SparseColors the reader takes entries and counts from their spans, not the offsets.
  MapReader<LookupT> reader{s.mesh.tri_vertices,
                            map_offset,
                            prev,
                            s.emissive,
                            lookup,
                            fibonacci_radius(cfg.viewpoints),
                            Vec3(bg),
                            sparse,
                            first_reads,
                            hemisphere,
                            order.slot};
  std::int64_t rays = 0;
  const bool with_gather = cfg.gather_rays > 0 && it > 0;
  if (with_gather) {
    DiffuseGather<LookupT> g{s.mesh.accel,     reader,
                             s.mesh.positions, s.normal,
                             s.diffuse,        gather,
                             cfg.gather_rays,  it,
                             cfg.seed,         s.mesh.coordinate_bound};
    std::int64_t r = 0;
    Kokkos::parallel_reduce("rtmini::bake::diffuse_gather",
                            Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(begin, end),
                            g, r);
    rays += r;
  }
  const ItemRange items = item_range(map_offset, begin, end);
  const std::int64_t item_begin = items.first;
  MirrorIteration<LookupT> m{s.mesh.accel,
                             reader,
                             s.mesh.positions,
                             s.normal,
                             s.diffuse,
                             s.reflective,
                             base,
                             gather,
                             s.viewpoints,
                             order.view,
                             map_offset,
                             cache,
                             traced,
                             next,
                             begin,
                             end,
                             item_begin,
                             cache_offset,
                             it,
                             with_gather,
                             mode,
                             s.mesh.coordinate_bound};
  m.two_sided = cfg.two_sided;
  return rays + trace_items("rtmini::bake::shade", items, m);
}
}  // namespace

void Chef::to_viewpoint_order(std::int64_t begin, std::int64_t end,
                              Kokkos::View<const Vec3f*, MemSpace> from,
                              Kokkos::View<Vec3f*, MemSpace> to) const {
  const auto offset = map_offset_;
  const auto order = order_.view;
  const ItemRange items = item_range(offset, begin, end);
  Kokkos::parallel_for(
      "rtmini::bake::to_viewpoint_order",
      Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>(items.first, items.end),
      KOKKOS_LAMBDA(std::int64_t item) {
        const std::int64_t v = vertex_of_item(offset, begin, end, item);
        const std::int64_t first = offset(v);
        const bool single = offset(v + 1) - first == 1;
        to(single ? item : first + order(item - first)) = from(item);
      });
}

std::int64_t Chef::bake_iteration(int it, std::int64_t begin, std::int64_t end,
                                  std::int64_t cache_offset, HitCacheMode cache,
                                  Kokkos::View<const Vec3f*, MemSpace> prev,
                                  Kokkos::View<Vec3f*, MemSpace> next) {
  if (cache == HitCacheMode::kFill && caches_hits_ && cache_.extent(0) == 0)
    cache_ = Kokkos::View<CachedHit*, MemSpace>("rtmini::bake::hit_cache", local_items_);
  if (cache == HitCacheMode::kTraced ? traced_.extent(0) == 0
                                     : cache != HitCacheMode::kOff && cache_.extent(0) == 0)
    cache = HitCacheMode::kOff;
  const HemisphereMap hemisphere = hemisphere_map();
  return with_lookup([&](const auto& lookup) {
    return run_iteration(scene_, config_, lookup, base_, gather_, cache_, traced_, map_offset_,
                         sparse_, first_reads_, order_, it, begin, end, cache_offset, cache, prev,
                         next, hemisphere);
  });
}

std::int64_t Chef::bake_iteration_of(const OwnerPart& part, int it, std::int64_t begin,
                                     std::int64_t end, std::int64_t cache_offset,
                                     HitCacheMode cache) {
  const HemisphereMap hemisphere = hemisphere_map();
  return with_lookup([&](const auto& lookup) {
    return run_iteration(scene_, config_, lookup, part.base, gather_, part.cache, part.traced,
                         part.map_offset, part.sparse, part.first_reads, order_, it, begin, end,
                         cache_offset, cache, part.prev, part.next, hemisphere);
  });
}

OwnerPart Chef::own_part(HitCacheMode mode) const {
  OwnerPart p;
  p.base = base_;
  if (mode == HitCacheMode::kUse) p.cache = cache_;
  if (mode == HitCacheMode::kTraced) p.traced = traced_;
  p.map_offset = map_offset_;
  p.sparse = sparse_;
  p.first_reads = first_reads_;
  return p;
}

void Chef::adopt_part(const OwnerPart& shared) {
  base_ = shared.base;
  if (shared.cache.extent(0) > 0) cache_ = shared.cache;
  if (shared.traced.extent(0) > 0) traced_ = shared.traced;
}

}  // namespace rtmini::bake
