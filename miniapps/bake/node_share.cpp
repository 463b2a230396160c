#include "node_share.hpp"

#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "rtmini/io/error.hpp"

namespace rtmini::bake {

namespace {

static_assert(std::atomic<std::int64_t>::is_always_lock_free,
              "the claim counters live in memory mapped by several processes: they must be "
              "lock-free (address-free) atomics");

constexpr std::size_t kAlign = 64;
constexpr std::size_t kHitBytes = std::max(sizeof(CachedHit), sizeof(TracedHit));

std::size_t aligned(std::size_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

// Hands out aligned regions of one segment in a fixed order (at == nullptr: sizes only).
class Carver {
 public:
  explicit Carver(unsigned char* at) : at_(at) {}
  template <class T>
  T* take(std::int64_t count, std::size_t bytes_each = sizeof(T)) {
    T* p = at_ ? reinterpret_cast<T*>(at_ + used_) : nullptr;
    used_ += aligned(static_cast<std::size_t>(count) * bytes_each);
    return p;
  }
  std::size_t used() const { return used_; }

 private:
  unsigned char* at_;
  std::size_t used_ = 0;
};

// On the rank's threads (Kokkos' host deep copy runs in parallel): a rank of 8 threads copies
// its hits into the segment 8 times faster than one memcpy.
template <class T>
void copy_into(T* to, const T* from, std::int64_t count) {
  const std::size_t n = static_cast<std::size_t>(count);
  if (count > 0 && to != from)
    Kokkos::deep_copy(compat::host_view(to, n), compat::host_view(from, n));
}

template <class View>
std::int64_t extent(const View& v) {
  return static_cast<std::int64_t>(v.extent(0));
}

template <class T>
Kokkos::View<T*, MemSpace> view_of(T* at, std::int64_t n) {
  return Kokkos::View<T*, MemSpace>(at, static_cast<std::size_t>(n));
}

// What `mine` uses of a segment's room; throws if it does not fit (a planning error).
SegmentSizes used_by(const OwnerPart& p, const SegmentSizes& room, std::int64_t pieces,
                     int first_iteration, int iterations, int first_prev) {
  SegmentSizes s;
  s.vertices = extent(p.base);
  s.map_colors = extent(p.prev);
  s.halo_colors = extent(p.sparse.halo);
  s.traced = extent(p.traced) > 0 ? 1 : 0;
  s.hits = s.traced ? extent(p.traced) : extent(p.cache);
  s.sparse = p.sparse.empty() ? 0 : 1;
  s.sparse_map_colors = p.sparse.map_colors;
  s.mask_words = extent(p.sparse.mask);
  s.kept_words = extent(p.sparse.kept);
  s.read_flags = extent(p.first_reads.flags);
  // A rank whose hits read no remote vertex has no read flags, and its segment no room for the
  // first iteration's tables (carve): it publishes none, and a rank that takes its pieces reads
  // every colour from its map. (Published with them, the tables were copied over the hits and
  // read back as garbage by such a rank: a crash at 2 ranks on two closed rooms.)
  s.first_reads = extent(p.first_reads.owned) > 0 && s.read_flags > 0 ? 1 : 0;
  s.pieces = pieces;
  s.iterations = iterations + 1;
  s.first_prev = first_prev;
  s.first_iteration = first_iteration;
  const bool fits = s.vertices <= room.vertices && s.map_colors == room.map_colors &&
                    s.halo_colors <= room.halo_colors && s.hits <= room.hits &&
                    s.sparse <= room.sparse && s.mask_words <= room.mask_words &&
                    s.kept_words <= room.kept_words && s.pieces <= room.pieces &&
                    s.read_flags <= room.read_flags && s.iterations <= room.iterations;
  if (!fits) throw std::logic_error("bake: node sharing: a rank's part outgrew its segment");
  return s;
}

// Calls f on every array of the scene (all only read once uploaded). An array added to the
// scene and not listed here still works; each rank keeps its own copy of it.
template <class F>
void for_each_scene_array(BakeSceneDevice& s, F&& f) {
  DeviceMesh<MemSpace>& m = s.mesh;
  f(m.positions);
  f(m.tris);
  f(m.tri_vertices);
  f(m.tri_face);
  f(m.tri_material);
  f(m.tri_object);
  f(m.materials);
  bvh::Bvh<MemSpace>& b = m.accel;
  f(b.nodes);
  f(b.wide);
  f(b.leaves);
  f(b.qwide);
  f(b.qwide_tris);
  f(b.qwide_prim);
  f(b.compact);
  f(b.tris);
  f(b.prim);
  f(s.normal);
  f(s.diffuse);
  f(s.reflective);
  f(s.emissive);
  f(s.color_offset);
  f(s.lights);
  f(s.viewpoints);
}

template <class View>
std::size_t bytes_of(const View& v) {
  if (!v.span_is_contiguous()) throw std::logic_error("bake: node sharing: a scene array has gaps");
  return v.span() * sizeof(typename View::value_type);
}

}  // namespace

std::size_t NodeShare::carve(unsigned char* at, const SegmentSizes& s, Segment* out) {
  Carver c(at);
  Segment seg;
  c.take<SegmentSizes>(2);  // room, used
  seg.counters = c.take<PaddedCounter>(s.iterations);
  seg.pieces = c.take<TracePiece>(s.pieces);
  seg.base = c.take<Vec3>(s.vertices);
  seg.map_offset = c.take<std::int64_t>(s.vertices + 1);
  seg.span = c.take<ColorSpan>(s.sparse ? s.vertices : 0);
  seg.mask = c.take<std::uint64_t>(s.mask_words);
  seg.kept = c.take<std::int32_t>(s.kept_words);
  const std::int64_t first_reads_vertices = s.read_flags > 0 ? s.vertices : 0;
  seg.owned = c.take<char>(first_reads_vertices);
  seg.remote_base = c.take<Vec3f>(first_reads_vertices);
  seg.read_at = c.take<std::int64_t>(first_reads_vertices > 0 ? first_reads_vertices + 1 : 0);
  // The flags last, on pages of their own: release_read_flags gives them back.
  seg.flags = c.take<char>(s.read_flags > 0 ? s.read_flags + 4096 : 0);
  seg.hits = c.take<unsigned char>(s.hits_elsewhere ? 0 : s.hits, kHitBytes);
  seg.buffer[0] = c.take<Vec3f>(s.map_elsewhere ? 0 : s.map_colors);
  seg.buffer[1] = c.take<Vec3f>(s.map_elsewhere ? 0 : s.map_colors);
  seg.halo = c.take<Vec3f>(s.halo_colors);
  seg.room = s;
  if (out) *out = seg;
  return c.used();
}

// The flags start on a page boundary, so that their pages can be given back alone.
static char* page_aligned(char* p) {
  const std::uintptr_t a = reinterpret_cast<std::uintptr_t>(p);
  return reinterpret_cast<char*>((a + 4095) & ~std::uintptr_t(4095));
}

Kokkos::View<char*, MemSpace> NodeShare::read_flags() const {
  return view_of(page_aligned(my_segment_.flags), my_segment_.room.read_flags);
}

void NodeShare::release_read_flags() {
  if (my_segment_.room.read_flags <= 0) return;
  const std::size_t bytes = static_cast<std::size_t>(my_segment_.room.read_flags) / 4096 * 4096;
  // On shared memory MADV_REMOVE frees the pages themselves, not only this process's mapping.
  if (bytes > 0) madvise(page_aligned(my_segment_.flags), bytes, MADV_REMOVE);
}

Kokkos::View<Vec3f*, MemSpace> NodeShare::map_buffer(int which) const {
  return view_of(my_segment_.buffer[which], my_segment_.room.map_colors);
}

Kokkos::View<Vec3f*, MemSpace> NodeShare::halo(std::int64_t colors) const {
  if (colors > my_segment_.room.halo_colors)
    throw std::logic_error("bake: node sharing: the halo outgrew its room");
  return view_of(my_segment_.halo, colors);
}

#ifdef RTMINI_HAVE_MPI

namespace {

// Collective over `comm`: the node's communicator and an MPI shared-memory window with `bytes`
// in this rank's segment (each segment on its own pages), open for load/store access until
// MPI_Finalize. Returns this rank's segment. `what` names the window in the error (IoError).
unsigned char* open_node_window(const Communicator& comm, std::size_t bytes, const char* what,
                                MPI_Comm& node, MPI_Win& win) {
  // Every rank is alive here (a failed peer ends this barrier with PeerFailure): the blocking
  // window calls below cannot wait on a rank that has gone.
  comm.barrier();
  node = comm.split_node();
  MPI_Comm_set_errhandler(node, MPI_ERRORS_RETURN);
  MPI_Info info = MPI_INFO_NULL;
  MPI_Info_create(&info);
  // Each rank's segment on its own pages, first touched by the rank that writes it.
  MPI_Info_set(info, "alloc_shared_noncontig", "true");
  unsigned char* mine = nullptr;
  const int rc = MPI_Win_allocate_shared(static_cast<MPI_Aint>(bytes), 1, info, node, &mine, &win);
  MPI_Info_free(&info);
  if (rc != MPI_SUCCESS)
    throw IoError(std::string("bake --node-sharing: an MPI shared-memory window for ") + what +
                  " of " + std::to_string(bytes) +
                  " bytes could not be allocated (is the node's shared memory, e.g. /dev/shm, "
                  "large enough?)");
  MPI_Win_lock_all(MPI_MODE_NOCHECK, win);
  return mine;
}

// Node barrier with the window's memory synchronisation: afterwards every rank of the node sees
// what every other wrote to the window before it.
void node_window_barrier(const Communicator& comm, MPI_Comm node, MPI_Win win) {
  MPI_Win_sync(win);  // this rank's writes to the window are visible ...
  MPI_Request req = MPI_REQUEST_NULL;
  MPI_Ibarrier(node, &req);
  comm.wait(req);     // ... once every rank of the node has made them so (or a peer failed)
  MPI_Win_sync(win);  // and this rank sees theirs
}

// Where node rank r's segment of a shared window is mapped in this process.
unsigned char* segment_of(MPI_Win win, int r) {
  MPI_Aint bytes = 0;
  int disp = 1;
  void* at = nullptr;
  MPI_Win_shared_query(win, r, &bytes, &disp, &at);
  return static_cast<unsigned char*>(at);
}

// Not MPI_Win_free: it is collective, and a destructor may run on one rank's error path while
// the others wait elsewhere (they would hang). The window goes with MPI_Finalize.
void close_node_window(MPI_Win win) {
  if (win != MPI_WIN_NULL) MPI_Win_unlock_all(win);
}

}  // namespace

NodeShare::NodeShare(const Communicator& comm, const SegmentSizes& room, const NodeHits* hits,
                     const NodeMap* map)
    : hits_(hits), map_(map) {
  SegmentSizes r = room;
  r.hits_elsewhere = hits ? 1 : 0;
  r.map_elsewhere = map ? 1 : 0;
  if (map && map->colors() != r.map_colors)
    throw std::logic_error("bake: node sharing: the node's map does not fit the map's layout");
  room_bytes_ = carve(nullptr, r, nullptr);
  mine_ = open_node_window(comm, room_bytes_, "the maps", node_, win_);
  MPI_Comm_rank(node_, &node_rank_);
  MPI_Comm_size(node_, &node_size_);
  carve(mine_, r, &my_segment_);
  point_elsewhere(node_rank_, my_segment_);
  std::memcpy(mine_, &r, sizeof r);
}

// Where segment r's hit records and map buffers are when they live in another window.
void NodeShare::point_elsewhere(int r, Segment& s) const {
  if (s.room.hits_elsewhere) s.hits = hits_->records(r);
  if (s.room.map_elsewhere) {
    s.buffer[0] = map_->buffer(0);
    s.buffer[1] = map_->buffer(1);
  }
}

NodeShare::~NodeShare() { close_node_window(win_); }

void NodeShare::publish(const Communicator& comm, const OwnerPart& mine,
                        const std::vector<TracePiece>& pieces, int first_iteration,
                        int iterations) {
  Segment& seg = my_segment_;
  const int first_prev = mine.prev.data() == seg.buffer[0] ? 0 : 1;
  if (mine.prev.data() != seg.buffer[first_prev] || mine.next.data() != seg.buffer[1 - first_prev])
    throw std::logic_error("bake: node sharing: the maps are not the segment's");
  const SegmentSizes used = used_by(mine, seg.room, static_cast<std::int64_t>(pieces.size()),
                                    first_iteration, iterations, first_prev);
  std::memcpy(mine_ + sizeof(SegmentSizes), &used, sizeof used);
  if (segments_.empty())  // the first publication: no counter is in use yet
    for (std::int64_t i = 0; i < used.iterations; ++i) {
      new (&seg.counters[i]) PaddedCounter;
      seg.counters[i].value.store(0);
    }
  copy_into(seg.pieces, pieces.data(), used.pieces);
  copy_into(seg.base, mine.base.data(), used.vertices);
  copy_into(seg.map_offset, mine.map_offset.data(), used.vertices + 1);
  if (used.sparse) copy_into(seg.span, mine.sparse.span.data(), used.vertices);
  copy_into(seg.mask, mine.sparse.mask.data(), used.mask_words);
  copy_into(seg.kept, mine.sparse.kept.data(), used.kept_words);
  if (used.first_reads) {
    copy_into(seg.owned, mine.first_reads.owned.data(), used.vertices);
    copy_into(seg.remote_base, mine.first_reads.base.data(), used.vertices);
    copy_into(seg.read_at, mine.first_reads.at.data(), used.vertices + 1);
    if (mine.first_reads.flags.data() != page_aligned(seg.flags))
      throw std::logic_error("bake: node sharing: the read flags are not the segment's");
  }
  if (used.traced)
    copy_into(reinterpret_cast<TracedHit*>(seg.hits), mine.traced.data(), used.hits);
  else
    copy_into(reinterpret_cast<CachedHit*>(seg.hits), mine.cache.data(), used.hits);
  copy_into(seg.halo, mine.sparse.halo.data(), used.halo_colors);

  // Every segment is complete before anyone reads another's sizes.
  node_barrier(comm);
  segments_.resize(static_cast<std::size_t>(node_size_));
  for (int r = 0; r < node_size_; ++r) {
    unsigned char* at = segment_of(win_, r);
    SegmentSizes header[2];  // room, used
    std::memcpy(header, at, sizeof header);
    Segment& s = segments_[static_cast<std::size_t>(r)];
    carve(at, header[0], &s);
    point_elsewhere(r, s);
    s.used = header[1];
  }
}

void NodeShare::node_barrier(const Communicator& comm) const {
  node_window_barrier(comm, node_, win_);
}

NodeScene::NodeScene(const Communicator& comm, BakeSceneDevice& scene) {
  for_each_scene_array(scene, [&](auto& v) { bytes_ += aligned(bytes_of(v)); });
  const bool first = comm.node_rank() == 0;
  unsigned char* mine = open_node_window(comm, first ? bytes_ : 0, "the scene", node_, win_);
  if (first) {
    std::size_t at = 0;
    for_each_scene_array(scene, [&](auto& v) {
      copy_into(mine + at, reinterpret_cast<const unsigned char*>(v.data()),
                static_cast<std::int64_t>(bytes_of(v)));
      at += aligned(bytes_of(v));
    });
  }
  node_window_barrier(comm, node_, win_);
  unsigned char* shared = segment_of(win_, 0);
  std::size_t at = 0;
  for_each_scene_array(scene, [&](auto& v) {
    using View = std::decay_t<decltype(v)>;
    const std::size_t bytes = bytes_of(v);
    // Same type, same layout, now not owning its memory: the rank's own copy is freed here.
    if (bytes > 0) v = View(reinterpret_cast<typename View::pointer_type>(shared + at), v.layout());
    at += aligned(bytes);
  });
  // The builder's one allocation behind nodes, tris and prim (bvh.hpp), no longer viewed.
  scene.mesh.accel.storage = {};
}

NodeScene::~NodeScene() { close_node_window(win_); }

NodeHits::NodeHits(const Communicator& comm, std::int64_t hits,
                   const std::vector<TracePiece>& pieces) {
  const std::int64_t n = static_cast<std::int64_t>(pieces.size());
  unsigned char* mine =
      open_node_window(comm, carve(nullptr, hits, n, nullptr), "the hit records", node_, win_);
  int ranks = 1;
  MPI_Comm_rank(node_, &node_rank_);
  MPI_Comm_size(node_, &ranks);
  Segment seg;
  carve(mine, hits, n, &seg);
  const std::int64_t header[2] = {hits, n};
  std::memcpy(mine, header, sizeof header);
  new (seg.counter) std::atomic<std::int64_t>(0);
  if (n > 0) std::memcpy(seg.piece, pieces.data(), pieces.size() * sizeof(TracePiece));
  node_window_barrier(comm, node_, win_);
  segments_.resize(static_cast<std::size_t>(ranks));
  for (int r = 0; r < ranks; ++r) {
    unsigned char* at = segment_of(win_, r);
    std::int64_t h[2];  // hits, pieces
    std::memcpy(h, at, sizeof h);
    carve(at, h[0], h[1], &segments_[static_cast<std::size_t>(r)]);
  }
}

NodeHits::~NodeHits() { close_node_window(win_); }

// The node's first rank holds both buffers (its pages are taken as the ranks write their own
// vertices); every rank maps them at their place in its address space.
NodeMap::NodeMap(const Communicator& comm, std::int64_t colors) : colors_(colors) {
  const std::size_t buffer_bytes = aligned(static_cast<std::size_t>(colors) * sizeof(Vec3f));
  const bool first = comm.node_rank() == 0;
  open_node_window(comm, first ? 2 * buffer_bytes : 0, "the node's map", node_, win_);
  unsigned char* at = segment_of(win_, 0);
  buffer_[0] = reinterpret_cast<Vec3f*>(at);
  buffer_[1] = reinterpret_cast<Vec3f*>(at + buffer_bytes);
}

NodeMap::~NodeMap() { close_node_window(win_); }

void NodeMap::barrier(const Communicator& comm) const { node_window_barrier(comm, node_, win_); }

void NodeHits::barrier(const Communicator& comm) const { node_window_barrier(comm, node_, win_); }

#else

NodeShare::NodeShare(const Communicator&, const SegmentSizes&, const NodeHits*, const NodeMap*) {
  throw InputError("bake --node-sharing needs a build with MPI");
}
NodeShare::~NodeShare() = default;
NodeScene::NodeScene(const Communicator&, BakeSceneDevice&) {
  throw InputError("bake --node-sharing needs a build with MPI");
}
NodeScene::~NodeScene() = default;
void NodeShare::publish(const Communicator&, const OwnerPart&, const std::vector<TracePiece>&, int,
                        int) {}
void NodeShare::node_barrier(const Communicator&) const {}
NodeHits::NodeHits(const Communicator&, std::int64_t, const std::vector<TracePiece>&) {
  throw InputError("bake --node-sharing needs a build with MPI");
}
NodeHits::~NodeHits() = default;
void NodeHits::barrier(const Communicator&) const {}
NodeMap::NodeMap(const Communicator&, std::int64_t) {
  throw InputError("bake --node-sharing needs a build with MPI");
}
NodeMap::~NodeMap() = default;
void NodeMap::barrier(const Communicator&) const {}

#endif

bool claim_pieces(std::atomic<std::int64_t>& counter, std::int64_t pieces, int node_size,
                  std::int64_t& first, std::int64_t& end) {
  const std::int64_t left = pieces - counter.load(std::memory_order_relaxed);
  if (left <= 0) return false;
  const std::int64_t want = std::max<std::int64_t>(1, left / (2 * node_size));
  first = counter.fetch_add(want, std::memory_order_relaxed);
  end = std::min(first + want, pieces);
  return first < end;
}

TracePiece merge_pieces(const TracePiece* p, std::int64_t& first, std::int64_t end,
                        std::int64_t& pieces) {
  TracePiece run = p[first];
  pieces = 1;
  // Consecutive pieces of one range: their vertices and hit slots continue the run's.
  for (++first; first < end && p[first].range == run.range && p[first].begin == run.end; ++first) {
    run.end = p[first].end;
    ++pieces;
  }
  return run;
}

bool NodeShare::claim(int r, int it, std::int64_t& first, std::int64_t& end) const {
  const Segment& s = segments_[static_cast<std::size_t>(r)];
  return claim_pieces(s.counters[it].value, s.used.pieces, node_size_, first, end);
}

TracePiece NodeShare::next_run(int r, std::int64_t& first, std::int64_t end,
                               std::int64_t& pieces) const {
  return merge_pieces(segments_[static_cast<std::size_t>(r)].pieces, first, end, pieces);
}

// A segment of the hit records' window: its sizes, the trace's claim counter (a cache line of
// its own), the pieces, then the records on pages of their own.
std::size_t NodeHits::carve(unsigned char* at, std::int64_t hits, std::int64_t pieces,
                            Segment* out) {
  Carver c(at);
  Segment seg;
  seg.hits = hits;
  seg.pieces = pieces;
  c.take<std::int64_t>(2);
  seg.counter = c.take<std::atomic<std::int64_t>>(1, kAlign);
  seg.piece = c.take<TracePiece>(pieces);
  // The records start on the first page boundary within the next 4096 bytes.
  char* page_room = c.take<char>(4096);
  if (at) seg.records = reinterpret_cast<unsigned char*>(page_aligned(page_room));
  c.take<unsigned char>(hits, kHitBytes);
  if (out) *out = seg;
  return c.used();
}

Kokkos::View<TracedHit*, MemSpace> NodeHits::traced(int r) const {
  const Segment& s = segments_[static_cast<std::size_t>(r)];
  return view_of(reinterpret_cast<TracedHit*>(s.records), s.hits);
}

bool NodeHits::claim(int r, std::int64_t& first, std::int64_t& end) const {
  const Segment& s = segments_[static_cast<std::size_t>(r)];
  return claim_pieces(*s.counter, s.pieces, node_size(), first, end);
}

TracePiece NodeHits::next_run(int r, std::int64_t& first, std::int64_t end,
                              std::int64_t& pieces) const {
  return merge_pieces(segments_[static_cast<std::size_t>(r)].piece, first, end, pieces);
}

OwnerPart NodeShare::part(int r, int it) const {
  const Segment& s = segments_[static_cast<std::size_t>(r)];
  const SegmentSizes& n = s.used;
  OwnerPart p;
  p.base = view_of(s.base, n.vertices);
  p.map_offset = view_of(s.map_offset, n.vertices + 1);
  if (n.traced)
    p.traced = view_of(reinterpret_cast<TracedHit*>(s.hits), n.hits);
  else
    p.cache = view_of(reinterpret_cast<CachedHit*>(s.hits), n.hits);
  const int prev = static_cast<int>((n.first_prev + (it - n.first_iteration)) % 2);
  p.prev = view_of(s.buffer[prev], n.map_colors);
  p.next = view_of(s.buffer[1 - prev], n.map_colors);
  if (n.sparse) {
    p.sparse.span = view_of<const ColorSpan>(s.span, n.vertices);
    p.sparse.mask = view_of<const std::uint64_t>(s.mask, n.mask_words);
    p.sparse.kept = view_of<const std::int32_t>(s.kept, n.kept_words);
    p.sparse.map_colors = n.sparse_map_colors;
    p.sparse.halo = view_of<const Vec3f>(s.halo, n.halo_colors);
  }
  if (n.first_reads) {
    p.first_reads.owned = view_of<const char>(s.owned, n.vertices);
    p.first_reads.base = view_of<const Vec3f>(s.remote_base, n.vertices);
    p.first_reads.at = view_of<const std::int64_t>(s.read_at, n.vertices + 1);
    p.first_reads.flags = view_of(page_aligned(s.flags), n.read_flags);
  }
  return p;
}

}  // namespace rtmini::bake
