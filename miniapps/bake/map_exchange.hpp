#pragma once
// The distributed colour map (owner computes): each rank stores the colours of the vertices it
// owns (its map, in vertex order, double-buffered: an iteration reads one and writes the other)
// plus those of the remote vertices its rays read (its halo, held once, apart from the map). The
// halo is fixed (mirror hits are geometry only), so the exchange that refreshes it after each
// iteration is planned once and replayed: every owner packs the colours each reader asked for
// (only the viewpoints its lookups read), one all-to-all exchange (pairwise: alltoallv_records)
// moves them, and they land in the reader's halo as they arrive: the halo is laid out in the order
// the exchange receives it (by owner rank, then by entry), so the receive buffer is the halo
// itself. A remote vertex keeps only the viewpoints this rank's lookups read (SparseColors,
// map_reader.hpp), so a rank holds what it owns (twice) plus what it reads (once).
#include <cstdint>
#include <type_traits>
#include <vector>

#include "bake_scene.hpp"
#include "kitchen.hpp"
#include "map_reader.hpp"
#include "rtmini/parallel/communicator.hpp"

namespace rtmini::bake {

// Where each vertex's colours sit in this rank's map and halo. Entries are numbered map first
// (0 .. colors()), then halo (colors() .. colors() + halo_colors), as SparseColors reads them.
// On a host backend the device views are the host vectors themselves (make_halo_layout): moved,
// never copied.
struct MapLayout {
  MapLayout() = default;
  MapLayout(MapLayout&&) = default;
  MapLayout& operator=(MapLayout&&) = default;
  MapLayout(const MapLayout&) = delete;
  MapLayout& operator=(const MapLayout&) = delete;

  std::vector<std::int64_t> offset;  // vertices + 1, the map's entries; others span none
  // The halo: first halo entry per vertex (-1: not in the halo; empty: no halo), in the
  // exchange's receive order; its sparse vertices (SparseColors): first mask word per vertex (-1
  // dense), the mask words and the kept viewpoints before each word.
  std::vector<std::int64_t> halo_at;
  std::vector<std::int64_t> halo_rank_at;  // first halo entry of each owner rank, and the end
  std::int64_t halo_colors = 0;
  std::vector<std::int64_t> mask_at;
  std::vector<std::uint64_t> mask;
  std::vector<std::int32_t> kept;
  Kokkos::View<std::int64_t*, MemSpace> device;  // offset
  SparseColors sparse;  // device copies (without the halo's colours); empty: no halo, all dense

  std::int64_t colors() const { return offset.back(); }
  // Bytes of the tables (host and device copies; one where they share memory), not the colours.
  std::int64_t table_bytes() const;
  bool in_map(std::int64_t v) const { return offset[v + 1] > offset[v]; }
  bool in_halo(std::int64_t v) const { return !halo_at.empty() && halo_at[v] >= 0; }
  bool dense(std::int64_t v) const { return mask_at.empty() || mask_at[v] < 0; }
  // Whether vertex v keeps its viewpoint j, and where (only for kept ones).
  bool keeps(std::int64_t v, std::int64_t j) const {
    if (in_map(v)) return true;
    if (!in_halo(v)) return false;
    return dense(v) || ((mask[mask_at[v] + (j >> 6)] >> (j & 63)) & 1) != 0;
  }
  std::int64_t entry(std::int64_t v, std::int64_t j) const {
    if (in_map(v)) return offset[v] + j;
    const std::int64_t first = colors() + halo_at[v];
    return dense(v) ? first + j : sparse_entry(first, mask_at[v], mask.data(), kept.data(), int(j));
  }
};

// The layout holding the vertices flagged in `present` in its map (each with its full colour
// count), without a halo.
MapLayout make_map_layout(const BakeSceneHost& scene, const std::vector<char>& present);

// The layout of a rank of several: the vertices flagged in `own` in the map (its own, or with
// the node's one map every vertex of its node); in the halo every other vertex that `remote` (a
// layout without a halo) holds, ordered by owner rank, then by vertex (the order the exchange
// receives them). With `read` (one flag per entry of `remote`), a view-dependent halo vertex
// keeps only the viewpoints flagged; without, all.
MapLayout make_halo_layout(const BakeSceneHost& scene, const MapLayout& remote, const char* read,
                           const std::vector<int>& owner, const std::vector<char>& own);

// The colours (global entry numbers) that `rank` holds in its halo, in halo order: all of a
// dense vertex's, the kept viewpoints of a sparse one.
std::vector<std::int64_t> remote_entries(const BakeSceneHost& scene, const MapLayout& layout);

// Marks every vertex of `layout` dense in its SparseColors (no halo), with the scene's colour
// counts rather than the layout's (a layout that leaves remote vertices out).
void mark_dense(const BakeSceneHost& scene, MapLayout& layout);

// One colour per vertex from the vertices' owners (collective): `wanted` lists vertex ids,
// ascending; `own` holds this rank's colours by vertex id. Returns the colours of `wanted`.
std::vector<Vec3f> fetch_vertex_colors(const Communicator& comm, const std::vector<int>& owner,
                                       const std::vector<std::int64_t>& wanted,
                                       const std::vector<Vec3f>& own);

// Whether MPI can read and write the map's memory space directly: always for host memory; for
// device memory with a CUDA-aware MPI, detected at run time (Open MPI's MPIX_Query_cuda_support;
// RTMINI_MPI_DEVICE_BUFFERS=0 forces the host staging, for comparison). Never required: without
// it the exchange stages through host buffers.
bool mpi_takes_map_memory();

class MapExchange {
 public:
  // Plans the exchange (collective) for `layout`'s halo (make_halo_layout): remote_entries(scene,
  // layout), the colours (global entry numbers, scene.color_offset) this rank reads but does not
  // own, all of a vertex's or only those its lookups read, asked of their owners. The halo is
  // received into `halo_storage` (layout.halo_colors entries, zeros) when given (node work
  // sharing keeps it in the node's window, node_share.hpp), else into a view of its own.
  MapExchange(const Communicator& comm, const BakeSceneHost& scene, const MapLayout& layout,
              bool changed_only, Kokkos::View<Vec3f*, MemSpace> halo_storage = {},
              bool map_shared = false);

  // The halo's colours (layout.halo_colors, in halo order), as the last run left them: what
  // SparseColors::halo reads. A restart fills it before the first run.
  Kokkos::View<Vec3f*, MemSpace> halo() const { return recv_buf_; }

  // Refreshes the halo from the owners' colours in their `map` (collective); returns bytes
  // sent. `other`: the other of the two map buffers, the map of the iteration before, which the
  // last run sent; the next iteration overwrites all of it. The first run sends every halo
  // entry, packed in `other` (nothing reads it any more); later ones read it, then hold their
  // messages in it where they fit, unless the map is shared (`map_shared`, the node's one map,
  // whose other buffer the node's other ranks read and pack in too): then in buffers of the
  // exchange's own. With
  // `changed_only` (bake --exchange changed, the default), later runs send, per destination, only
  // the entries whose colour changed (bit for bit) since the last run, with a bitmask of the
  // destination's entries or a list of their indices, whichever is smaller; the receiver keeps the
  // last colour of the others. A view-independent vertex's colour, and a mirror colour whose
  // reflected path ends on such vertices, stop changing after an iteration or two, so later
  // exchanges shrink.
  std::int64_t run(const Communicator& comm, Kokkos::View<Vec3f*, MemSpace> map,
                   Kokkos::View<Vec3f*, MemSpace> other);

  std::int64_t send_colors() const { return total(send_counts_); }
  // Bytes held now: the send list (entries and first entry per peer) and the changed-only
  // runs' scratch (changed counts, the messages sent and received). The halo is halo().
  std::int64_t send_list_bytes() const;
  std::int64_t scratch_bytes() const;
  bool direct() const { return direct_; }  // MPI moves the map's own buffers (no host copies)
  std::int64_t recv_colors() const { return total(recv_counts_); }
  // Over the runs after the first: the colours sent (changed) and those a full send would have
  // sent, for the changed fraction.
  std::int64_t changed_colors() const { return changed_colors_; }
  std::int64_t offered_colors() const { return offered_colors_; }

  // The two kinds of run() (public only because nvcc rejects device lambdas in private members).
  std::int64_t run_full(const Communicator& comm, Kokkos::View<Vec3f*, MemSpace> map,
                        Kokkos::View<Vec3f*, MemSpace> spare);
  std::int64_t run_changed(const Communicator& comm, Kokkos::View<Vec3f*, MemSpace> map,
                           Kokkos::View<Vec3f*, MemSpace> previous,
                           Kokkos::View<Vec3f*, MemSpace> scratch);

  // Frees the buffers (the halo, the colours last sent, the scratch) once no exchange follows;
  // the counts above stay.
  void release();

 private:
  static std::int64_t total(const std::vector<int>& c) {
    std::int64_t s = 0;
    for (int x : c) s += x;
    return s;
  }
  // The words a changed-only message to or from a rank holds: as a bitmask or an index list.
  static std::int64_t mask_words(std::int64_t entries) { return (entries + 31) / 32; }
  std::vector<int> send_counts_, send_displs_, recv_counts_, recv_displs_;  // in colours
  // This rank's map entries that it sends, in send order: 4 bytes each (a rank's map has fewer
  // than 2^32 entries; checked), 8 with the global numbers they are asked by.
  using SendItem = std::uint32_t;
  Kokkos::View<SendItem*, MemSpace> send_items_;
  // The colours last received: the halo, in receive order. (What was last sent is the previous
  // iteration's map, which the owner holds anyway: no copy of it is kept.)
  Kokkos::View<Vec3f*, MemSpace> recv_buf_;
  bool direct_ = false;
  bool sent_ = false;                                  // the first (full) run is done
  bool changed_only_ = false;                          // bake --exchange changed
  bool map_shared_ = false;  // the map buffers are the node's (no scratch in them)
  Kokkos::View<std::int64_t*, MemSpace> first_entry_;  // send_displs_ and the send entries
  // Changed-only runs' scratch, kept from run to run: which send entries changed (a bit each),
  // the changed entries before each word of those bits, and the messages sent and received
  // (words) where they do not fit in the previous map's memory.
  Kokkos::View<std::uint32_t*, MemSpace> changed_bits_;
  Kokkos::View<std::int32_t*, MemSpace> changed_words_before_;
  Kokkos::View<std::uint32_t*, MemSpace> message_words_;
  std::int64_t changed_colors_ = 0, offered_colors_ = 0;
};

// Every rank's owned colours in the global (replicated) order, on the root only (empty
// elsewhere): for checkpoints and the reference comparison. `local`: the rank's map (host memory,
// layout.colors() entries).
std::vector<Vec3f> gather_global_map(const Communicator& comm, const BakeSceneHost& scene,
                                     const MapLayout& layout, const Vec3f* local,
                                     const std::vector<int>& owner);

// The entries of `layout` (map, then halo) copied out of a map in the global order (a restart).
std::vector<Vec3f> localise_map(const BakeSceneHost& scene, const MapLayout& layout,
                                const std::vector<Vec3f>& global);

// Records of raw bytes in MemSpace, for move_entry_records (any trivially copyable record type).
using RecordBytes = Kokkos::View<unsigned char*, MemSpace, Kokkos::MemoryUnmanaged>;

// Moves one record per colour entry from the ownership `from` to the ownership `to` (collective;
// both ascending vertex ranges over all vertices, as make_batches returns them): `mine` holds
// this rank's records of its `from` ranges in vertex order; `out` receives those of its `to`
// ranges, in vertex order. Both stay in MemSpace: records that stay on a rank are copied there
// (parallel copies, no host round trip: the serial host copies of a rank's traced hits cost
// about 9 % of its mirror trace on one thread, so about 70 % of it on a rank of 8 threads), the
// others go through one all-to-all exchange of MemSpace buffers when MPI takes that memory
// (mpi_takes_map_memory), else through host buffers.
void move_entry_records(const Communicator& comm, const BakeSceneHost& scene,
                        const std::vector<Batch>& from, const std::vector<Batch>& to,
                        RecordBytes mine, RecordBytes out, std::size_t record_bytes);
template <class T>
Kokkos::View<T*, MemSpace> move_entries(const Communicator& comm, const BakeSceneHost& scene,
                                        const std::vector<Batch>& from,
                                        const std::vector<Batch>& to,
                                        const Kokkos::View<T*, MemSpace>& mine) {
  static_assert(std::is_trivially_copyable<T>::value, "records move as bytes");
  std::int64_t n = 0;
  for (const Batch& b : to)
    if (b.rank == comm.rank()) n += scene.color_offset[b.end] - scene.color_offset[b.begin];
  // Every record of `out` is written (the `from` ranges cover every vertex).
  Kokkos::View<T*, MemSpace> out(
      Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::moved_entries"),
      static_cast<std::size_t>(n));
  const auto bytes = [](const Kokkos::View<T*, MemSpace>& v) {
    return RecordBytes(reinterpret_cast<unsigned char*>(v.data()), v.extent(0) * sizeof(T));
  };
  move_entry_records(comm, scene, from, to, bytes(mine), bytes(out), sizeof(T));
  return out;
}

}  // namespace rtmini::bake
