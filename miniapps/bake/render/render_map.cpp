#include "render_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "map_reader.hpp"
#include "rtmini/bvh/traverse.hpp"
#include "rtmini/parallel/spread_order.hpp"
#include "rtmini/report/hash.hpp"
#include "rtmini/sampling/rng.hpp"
#include "rtmini/sampling/sampling.hpp"

namespace rtmini::bake {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;

// With a progress line the frame is traced in time-sized dispatches (TimedChunks: a fixed 64
// equal ones cost 20-35 %), each of at least kMinDispatchPixels, its rows in a spread order
// (SpreadOrder: each dispatch a sample of the whole frame, so the ETA holds); without one, in one
// dispatch, row after row. Each pixel is independent and the hit count an integer sum, so the
// image and hash are the same either way.
constexpr std::int64_t kMinDispatchPixels = 32768;

// One pixel: spp camera rays, each coloured by MapReader::read at its closest hit along the
// ray direction (the camera-ray direction into the surface: the baker's viewpoint convention).
template <class LookupT>
struct RenderPixels {
  bvh::Bvh<MemSpace> accel;
  MapReader<LookupT> reader;
  DeviceCamera camera;
  Kokkos::View<float* [3], MemSpace> out;
  int width, spp, grid;
  std::uint64_t seed;
  SpreadOrder order;  // position -> pixel

  KOKKOS_INLINE_FUNCTION void operator()(std::int64_t pos, std::int64_t& hits) const {
    const std::int64_t pixel = order.item(pos);
    const int x = static_cast<int>(pixel % width), y = static_cast<int>(pixel / width);
    Vec3 sum(Real(0));
    for (int s = 0; s < spp; ++s) {
      Real sx = Real(0.5), sy = Real(0.5);
      if (spp > 1) {
        float u1, u2;
        Rng(seed, static_cast<std::uint64_t>(pixel), static_cast<std::uint32_t>(s))
            .uniform2(0u, u1, u2);
        sx = u1;
        sy = u2;
        // Jittered strata for the first grid^2 samples, plain uniform for the rest (as the Chef).
        if (s < grid * grid) stratified_2d(s, grid, Real(u1), Real(u2), sx, sy);
      }
      const Ray ray = camera.generate(Real(x) + sx, Real(y) + sy, Real(0.5), Real(0.5), Real(0.5),
                                      false, false);
      const Hit hit = bvh::closest_hit(accel, ray);
      if (hit.valid()) ++hits;
      sum += reader.read(hit.prim, hit.u, hit.v, ray.dir);
    }
    sum = sum * (Real(1) / Real(spp));
    out(pixel, 0) = static_cast<float>(sum.x);
    out(pixel, 1) = static_cast<float>(sum.y);
    out(pixel, 2) = static_cast<float>(sum.z);
  }
};

// A hemisphere map read with the KD-tree or grid lookup queries one over the stored half and its
// mirror images (one query per vertex instead of two, the same neighbours).
inline HemisphereMap hemisphere_for(const BakedMapDevice& map, const FibonacciKdTree<MemSpace>&) {
  HemisphereMap h = map.hemisphere;
  if (h.on()) h.mirrored = build_mirrored_kdtree<MemSpace>(map.viewpoints);
  return h;
}
inline HemisphereMap hemisphere_for(const BakedMapDevice& map, const SphereGrid<MemSpace>&) {
  HemisphereMap h = map.hemisphere;
  if (h.on()) h.mirrored_grid = build_mirrored_grid<MemSpace>(map.viewpoints);
  return h;
}
inline HemisphereMap hemisphere_for(const BakedMapDevice& map, const FibonacciInverse<MemSpace>&) {
  return map.hemisphere;
}

template <class LookupT>
std::int64_t run_kernel(const BakedMapDevice& map, const LookupT& lookup,
                        const DeviceCamera& camera, const RenderParams& p,
                        Kokkos::View<float* [3], MemSpace> out, ProgressLine* progress) {
  const MapReader<LookupT> reader{map.mesh.tri_vertices,
                                  map.color_offset,
                                  map.colors,
                                  Kokkos::View<Vec3*, MemSpace>(),
                                  lookup,
                                  fibonacci_radius(map.viewpoints),
                                  Vec3(p.background),
                                  SparseColors{},
                                  FirstReads{},
                                  hemisphere_for(map, lookup)};
  const int grid = static_cast<int>(std::sqrt(static_cast<double>(p.spp)) + 1e-9);
  const std::int64_t pixels = static_cast<std::int64_t>(p.width) * p.height;
  const bool shown = progress && progress->enabled();
  const RenderPixels<LookupT> kernel{map.mesh.accel,
                                     reader,
                                     camera,
                                     out,
                                     p.width,
                                     p.spp,
                                     grid,
                                     p.seed,
                                     shown ? SpreadOrder(pixels, p.width) : SpreadOrder()};
  std::int64_t hits = 0, begin = 0, end = 0;
  TimedChunks chunks(pixels, progress, kMinDispatchPixels);
  while (chunks.next(begin, end)) {
    std::int64_t dispatch_hits = 0;
    // A reduce into a host value returns once its pixels are done: the progress is real.
    Kokkos::parallel_reduce("rtmini::bake::render::pixels",
                            Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>,
                                                Kokkos::Schedule<Kokkos::Dynamic>>(begin, end),
                            kernel, dispatch_hits);
    hits += dispatch_hits;
    if (progress) progress->update(static_cast<double>(end), static_cast<double>(pixels));
  }
  return hits;
}

std::uint64_t bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

}  // namespace

RenderResult render_baked_map(const BakedMapDevice& map, const DeviceCamera& camera,
                              const RenderParams& p, ProgressLine* progress) {
  const std::int64_t pixels = static_cast<std::int64_t>(p.width) * p.height;
  Kokkos::View<float* [3], MemSpace> out("rtmini::bake::render::image", pixels);
  RenderResult r;
  if (p.lookup == Lookup::kGrid)
    r.hits =
        run_kernel(map, build_fibonacci_grid<MemSpace>(map.viewpoints), camera, p, out, progress);
  else if (p.lookup == Lookup::kKdTree)
    r.hits =
        run_kernel(map, build_fibonacci_kdtree<MemSpace>(map.viewpoints), camera, p, out, progress);
  else
    r.hits = run_kernel(map, build_fibonacci_inverse<MemSpace>(map.viewpoints), camera, p, out,
                        progress);
  r.rays = pixels * p.spp;
  auto host = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), out);
  r.image = Image(p.width, p.height, 3);
  for (std::int64_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) r.image.data[static_cast<std::size_t>(3 * i + c)] = host(i, c);
    // Same per-pixel mix as sketchtrace's colour hash, summed mod 2^64 (order-independent).
    const std::uint64_t v =
        mix64(bits(host(i, 0)) | bits(host(i, 1)) << 32) ^ mix64(bits(host(i, 2)) ^ 0x5bd1e995ULL);
    r.verification += hash_term(static_cast<std::uint64_t>(i), v);
  }
  return r;
}

}  // namespace rtmini::bake
