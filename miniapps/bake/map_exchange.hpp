#pragma once
// The distributed colour map (owner computes): each rank stores the colours of the vertices it
// owns plus the remote vertices its rays read (its halo), in one local array laid out in vertex
// order. A vertex that is absent holds no entry, so the local offsets keep every present
// vertex's colour count and the kernels index the local map exactly as they indexed the
// replicated one. The halo is fixed (mirror hits are geometry only), so the exchange that
// refreshes it after each iteration is planned once and replayed: every owner packs the colours
// each reader asked for (only the viewpoints its lookups read), one MPI_Alltoallv moves them,
// every reader scatters them into place.
#include <cstdint>
#include <vector>

#include "bake_scene.hpp"
#include "rtmini/parallel/communicator.hpp"

namespace rtmini::bake {

// Where each vertex's colours sit in this rank's map.
struct MapLayout {
  std::vector<std::int64_t> offset;  // vertices + 1; an absent vertex spans no entry
  Kokkos::View<std::int64_t*, MemSpace> device;
  std::int64_t colors() const { return offset.back(); }
  bool present(std::int64_t v) const { return offset[v + 1] > offset[v]; }
};

// The layout holding the vertices flagged in `present` (each with its full colour count).
MapLayout make_map_layout(const BakeSceneHost& scene, const std::vector<char>& present);

class MapExchange {
 public:
  // Plans the exchange (collective): `halo` lists, ascending, the colours (global entry
  // numbers, scene.color_offset) this rank reads but does not own: all of a vertex's, or only
  // those its lookups read; owner[v] is the rank that computes vertex v.
  MapExchange(const Communicator& comm, const BakeSceneHost& scene, const MapLayout& layout,
              const std::vector<int>& owner, const std::vector<std::int64_t>& halo);

  // Refreshes the halo entries of `map` from their owners (collective); returns bytes sent.
  std::int64_t run(const Communicator& comm, Kokkos::View<Vec3f*, MemSpace> map);

  std::int64_t send_colors() const { return total(send_counts_); }
  std::int64_t recv_colors() const { return total(recv_counts_); }

 private:
  static std::int64_t total(const std::vector<int>& c) {
    std::int64_t s = 0;
    for (int x : c) s += x;
    return s;
  }
  std::vector<int> send_counts_, send_displs_, recv_counts_, recv_displs_;  // in colours
  Kokkos::View<std::int64_t*, MemSpace> send_items_, recv_items_;           // local entries
  Kokkos::View<Vec3f*, MemSpace> send_buf_, recv_buf_;
  std::vector<Vec3f> host_send_, host_recv_;
};

// Every rank's owned colours in the global (replicated) order, on the root only (empty
// elsewhere): for the binary output, checkpoints and the reference comparison.
std::vector<Vec3f> gather_global_map(const Communicator& comm, const BakeSceneHost& scene,
                                     const MapLayout& layout, const std::vector<Vec3f>& local,
                                     const std::vector<int>& owner);

// The entries of `layout` copied out of a map in the global order (a restart).
std::vector<Vec3f> localise_map(const BakeSceneHost& scene, const MapLayout& layout,
                                const std::vector<Vec3f>& global);

}  // namespace rtmini::bake
