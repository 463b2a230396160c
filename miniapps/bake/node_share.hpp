#pragma once
// Work sharing between the ranks of a node (bake --node-sharing on; host backends).
//
// The owner-computes cut is fixed for a run, so each iteration waits for its slowest rank. On
// the lent 16-core hosts a rank's speed is a draw that drifts over seconds (about 7 % std; no cut
// predicts it: results/bake/distributed.md, seventeenth and eighteenth rounds), so 16 x 1 paid
// the slowest of 16 draws where 1 x 16's dynamic schedule paid their mean. Here the ranks of a
// node keep what an iteration of theirs reads and writes in one MPI shared-memory window (each
// rank its own segment: its two map buffers and halo, or on one node the node's one map
// (NodeMap), its hit records, base colours, map tables and its pieces), and a rank that has finished its own pieces takes the unclaimed pieces of the
// others, reading the owner's previous map and writing the owner's next one. A colour depends
// only on its entry and the previous map, so the output is bit-identical whoever computes it.
//
// Each rank's pieces are claimed through one atomic counter per iteration in its segment: no
// lock, no message. An iteration opens with a node barrier (every owner's exchange has filled
// its halo and previous map) and closes with one (every stolen piece is written before the
// owner exchanges or writes). Every mirror iteration shares, the first one too: there a stolen
// piece also flags, in the owner's flags, the remote colours its lookups read (FirstReads),
// from which the owner plans its halo; the part is published again after that plan. The
// mirror trace before the iterations is shared too where no recut follows it (one node,
// NodeHits): its cut balances BVH nodes to 2-3 %, but the ranks' speeds spread 1.15-1.18x
// max / mean over it at 16 x 1 (results/bake/distributed.md, twenty-third round).
//
// The maps and the halo live in the window from their allocation (map_buffer, halo): on the
// lent hosts first touching a page costs about 4 ms per MiB, so copying them in at the first
// shared iteration cost 0.12-0.25 s per run. What is copied in when sharing starts (publish) is
// the rest: hit records, base colours and the halo's tables, about a third of a segment.
#include <atomic>
#include <cstdint>
#include <vector>

#include "bake_scene.hpp"
#include "chef.hpp"
#include "rtmini/parallel/communicator.hpp"

namespace rtmini::bake {

// One dispatch of an iteration: whole vertices [begin, end) of one of a rank's ranges (the
// range-th), and the hit-cache slot of their first colour entry.
struct TracePiece {
  std::int64_t begin = 0, end = 0, cache_offset = 0, range = 0;
};

// What a segment holds, in elements: the room reserved when the window is made, then what is
// used of it once published.
struct SegmentSizes {
  std::int64_t vertices = 0, map_colors = 0, halo_colors = 0;
  std::int64_t hits = 0;  // hit records (the float cache or the traced hits: the larger size)
  std::int64_t hits_elsewhere = 0;  // the hit records are in NodeHits' window, not here
  std::int64_t map_elsewhere = 0;   // the map buffers are the node's one map (NodeMap), not here
  std::int64_t sparse = 0, sparse_map_colors = 0, mask_words = 0, kept_words = 0;
  std::int64_t pieces = 0, iterations = 0;
  std::int64_t read_flags = 0;   // FirstReads' flags (a fused first iteration); 0: none
  std::int64_t first_reads = 0;  // FirstReads published (owned, base, at, flags)
  std::int64_t traced = 0;       // the hits are TracedHit (else CachedHit)
  std::int64_t first_prev =
      0;  // which map buffer is the previous map at the first shared iteration
  std::int64_t first_iteration = 0;
};

// Whether this build can share work between a node's ranks: the map must live in host memory.
constexpr bool node_sharing_possible() {
  return Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible;
}

// The --node-sharing value that gives `c`'s choices.
inline const char* node_sharing_name(const BakeConfig& c) {
  if (c.share_scene) return c.share_work ? "on" : "scene";
  return c.share_work ? "work" : "off";
}

// One copy of the scene per node (--node-sharing scene or on; host backends). Every rank reads
// the whole mesh, BVH and per-vertex tables on every ray, and without sharing each of a node's
// ranks holds its own copy: 16 ranks of a 16-core node cycle 16 copies of the BVH through the
// shared last-level cache where 16 threads of one rank share one. Here the node's first rank
// copies the scene's arrays into one MPI shared-memory window and every rank's views are
// pointed into it; the ranks' own copies are freed. The arrays are only read from then on.
// (The window's pages are first touched by that rank: on a node of several sockets they sit on
// its socket.)
class NodeScene {
 public:
  // Collective over `comm` (every rank, whatever its node). Every rank of a node must have
  // uploaded the same scene: the copies are interchangeable, so which one is kept does not
  // change an answer.
  NodeScene(const Communicator& comm, BakeSceneDevice& scene);
  ~NodeScene();
  NodeScene(const NodeScene&) = delete;
  NodeScene& operator=(const NodeScene&) = delete;
  std::int64_t bytes() const { return static_cast<std::int64_t>(bytes_); }

 private:
  std::size_t bytes_ = 0;
#ifdef RTMINI_HAVE_MPI
  MPI_Comm node_ = MPI_COMM_NULL;
  MPI_Win win_ = MPI_WIN_NULL;
#endif
};

// The guided self-scheduling of both windows: claims the next pieces [first, end) of `pieces`
// through `counter` (a share of what is left: 1 / (2 x the node's ranks), at least one piece),
// so that a rank of several threads runs few, long dispatches (each piece ends in a tail where
// its threads wait for the last vertex) and the last claims, the ones that even out the ranks,
// are single pieces. False once all are claimed.
bool claim_pieces(std::atomic<std::int64_t>& counter, std::int64_t pieces, int node_size,
                  std::int64_t& first, std::int64_t& end);
// The pieces of p from `first` on (before `end`) that continue one vertex range, merged into one
// dispatch; `first` moves past them, `pieces` is how many they were.
TracePiece merge_pieces(const TracePiece* p, std::int64_t& first, std::int64_t end,
                        std::int64_t& pieces);

// The node's traced hit records from the mirror trace on (--node-sharing on, one node: no recut
// moves hits after the trace). Each rank's segment holds its hit records (room for its colour
// entries), its trace pieces and one claim counter; a rank that has traced its own pieces takes
// the unclaimed pieces of the others and writes their hits into the owner's records, which the
// owner reads as its own: the same bits whoever traces a ray. NodeShare then points its
// segments' hit records here, so they are written once, by the trace, and never copied.
class NodeHits {
 public:
  // Collective over `comm`: the window, this rank's `hits` records (zeros) and its pieces.
  NodeHits(const Communicator& comm, std::int64_t hits, const std::vector<TracePiece>& pieces);
  ~NodeHits();
  NodeHits(const NodeHits&) = delete;
  NodeHits& operator=(const NodeHits&) = delete;

  int node_rank() const { return node_rank_; }
  int node_size() const { return static_cast<int>(segments_.size()); }
  // Rank r's (node rank) records, as traced hits and as raw bytes (NodeShare's segments).
  Kokkos::View<TracedHit*, MemSpace> traced(int r) const;
  unsigned char* records(int r) const { return segments_[static_cast<std::size_t>(r)].records; }
  bool claim(int r, std::int64_t& first, std::int64_t& end) const;
  TracePiece next_run(int r, std::int64_t& first, std::int64_t end, std::int64_t& pieces) const;
  // Node barrier with the window's memory synchronisation (after the trace: every record is in).
  void barrier(const Communicator& comm) const;

 private:
  struct Segment {
    std::int64_t hits = 0, pieces = 0;
    std::atomic<std::int64_t>* counter = nullptr;
    TracePiece* piece = nullptr;
    unsigned char* records = nullptr;
  };
  static std::size_t carve(unsigned char* at, std::int64_t hits, std::int64_t pieces, Segment* out);

  int node_rank_ = 0;
  std::vector<Segment> segments_;
#ifdef RTMINI_HAVE_MPI
  MPI_Comm node_ = MPI_COMM_NULL;
  MPI_Win win_ = MPI_WIN_NULL;
#endif
};

// The node's one map (--node-map on, with work shared between a node's ranks): both map
// buffers of every vertex the node's ranks own, in one MPI shared-memory window, laid out as one
// rank holding them would lay them out (MapLayout of the node's vertices). Each rank writes its
// own vertices' colours and reads any of the node's in place, as the threads of one rank do;
// only other nodes' vertices come through its halo and the exchanges. On one node that is no
// halo and no exchange at all: per-rank maps with halos cost 16 x 1 on bunny_room 0.10 s of
// exchanges (0.065 s with the halo plan after iteration 1) and 0.015 s of planning in a 1.37 s
// bake, where 1 x 16 has neither (results/bake/distributed.md, twenty-fifth round). The pages
// are first touched by the rank that writes them (its own vertices).
class NodeMap {
 public:
  // Collective over `comm`: room for `colors` colours twice (the node's; every rank of a node
  // passes the same).
  NodeMap(const Communicator& comm, std::int64_t colors);
  ~NodeMap();
  NodeMap(const NodeMap&) = delete;
  NodeMap& operator=(const NodeMap&) = delete;

  Vec3f* buffer(int which) const { return buffer_[which]; }
  std::int64_t colors() const { return colors_; }
  // Node barrier with the window's memory synchronisation: every rank's colours written before
  // it are seen by every rank after it (closes each iteration).
  void barrier(const Communicator& comm) const;

 private:
  std::int64_t colors_ = 0;
  Vec3f* buffer_[2] = {nullptr, nullptr};
#ifdef RTMINI_HAVE_MPI
  MPI_Comm node_ = MPI_COMM_NULL;
  MPI_Win win_ = MPI_WIN_NULL;
#endif
};

class NodeShare {
 public:
  // Collective over `comm` (every rank, whatever its node): makes the node's window with `room`
  // in this rank's segment (pages are taken only when touched). With `hits`, the segments'
  // hit records are those of NodeHits' window (made by every rank of the node); with `map`,
  // every segment's map buffers are the node's one map (room.map_colors: all of its colours).
  NodeShare(const Communicator& comm, const SegmentSizes& room, const NodeHits* hits = nullptr,
            const NodeMap* map = nullptr);
  ~NodeShare();
  NodeShare(const NodeShare&) = delete;
  NodeShare& operator=(const NodeShare&) = delete;

  // This rank's two map buffers (room.map_colors each) and its halo (the first `colors` of
  // room.halo_colors): zeros until written, like a fresh Kokkos view.
  Kokkos::View<Vec3f*, MemSpace> map_buffer(int which) const;
  Kokkos::View<Vec3f*, MemSpace> halo(std::int64_t colors) const;
  // This rank's FirstReads flags (room.read_flags, zeros): the fused first iteration's readers,
  // the owner and those that take its pieces, flag what they read in them.
  Kokkos::View<char*, MemSpace> read_flags() const;
  // Gives the flags' pages back once the halo is planned (they are not read again).
  void release_read_flags();

  // Collective over `comm`: this rank's part from iteration `first_iteration` on (its prev and
  // next must be the map buffers, its halo and flags the segment's), the rest of it copied into
  // the segment, and its pieces. Afterwards the rank works on part(node_rank(), it) (adopt it).
  // Published again when the part changes (the halo planned after a fused first iteration).
  void publish(const Communicator& comm, const OwnerPart& mine,
               const std::vector<TracePiece>& pieces, int first_iteration, int iterations);
  bool published() const { return !segments_.empty(); }

  int node_rank() const { return node_rank_; }
  int node_size() const { return node_size_; }
  std::int64_t segment_bytes() const { return static_cast<std::int64_t>(room_bytes_); }

  // Rank r's (node rank) part as iteration `it` reads and writes it: the two map buffers swap
  // roles every iteration, as the owner's prev and next do.
  OwnerPart part(int r, int it) const;
  // Claims the next pieces [first, end) of rank r in iteration `it` (claim_pieces).
  bool claim(int r, int it, std::int64_t& first, std::int64_t& end) const;
  // The pieces from `first` on that continue one vertex range of rank r (merge_pieces).
  TracePiece next_run(int r, std::int64_t& first, std::int64_t end, std::int64_t& pieces) const;

  // Node barriers around an iteration's pieces, with the memory synchronisation of the window.
  void open_iteration(const Communicator& comm) const { node_barrier(comm); }
  void close_iteration(const Communicator& comm) const { node_barrier(comm); }

 private:
  // Claim counters a cache line apart: every rank of the node hits them while the owner computes.
  struct alignas(64) PaddedCounter {
    std::atomic<std::int64_t> value;
  };
  struct Segment {
    SegmentSizes room, used;
    PaddedCounter* counters = nullptr;  // one per iteration
    TracePiece* pieces = nullptr;
    Vec3* base = nullptr;
    std::int64_t* map_offset = nullptr;
    ColorSpan* span = nullptr;
    std::uint64_t* mask = nullptr;
    std::int32_t* kept = nullptr;
    char *owned = nullptr, *flags = nullptr;  // FirstReads
    Vec3f* remote_base = nullptr;
    std::int64_t* read_at = nullptr;
    unsigned char* hits = nullptr;
    Vec3f *buffer[2] = {nullptr, nullptr}, *halo = nullptr;
  };
  // The regions of a segment at `at` with room `s` (at == nullptr: its size only).
  static std::size_t carve(unsigned char* at, const SegmentSizes& s, Segment* out);
  void point_elsewhere(int r, Segment& s) const;
  void node_barrier(const Communicator& comm) const;

  int node_rank_ = 0, node_size_ = 1;
  std::size_t room_bytes_ = 0;
  unsigned char* mine_ = nullptr;
  const NodeHits* hits_ = nullptr;  // where the hit records are (nullptr: in the segments)
  const NodeMap* map_ = nullptr;    // where the map buffers are (nullptr: in the segments)
  Segment my_segment_;
  std::vector<Segment> segments_;  // every rank's of the node, once published
#ifdef RTMINI_HAVE_MPI
  MPI_Comm node_ = MPI_COMM_NULL;
  MPI_Win win_ = MPI_WIN_NULL;
#endif
};

}  // namespace rtmini::bake
