#include "node_share.hpp"

#include <cstring>
#include <new>
#include <string>

#include "rtmini/io/error.hpp"

namespace rtmini::bake {

namespace {

static_assert(std::atomic<std::int64_t>::is_always_lock_free,
              "the claim counters live in memory mapped by several processes: they must be "
              "lock-free (address-free) atomics");

constexpr std::size_t kAlign = 64;
std::size_t aligned(std::size_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

// Hands out aligned regions of one segment in a fixed order (at == nullptr: sizes only).
class Carver {
 public:
  explicit Carver(char* at) : at_(at) {}
  template <class T>
  T* take(std::int64_t count) {
    T* p = at_ ? reinterpret_cast<T*>(at_ + used_) : nullptr;
    used_ += aligned(static_cast<std::size_t>(count) * sizeof(T));
    return p;
  }
  std::size_t used() const { return used_; }

 private:
  char* at_;
  std::size_t used_ = 0;
};

template <class T>
void copy_into(T* to, const T* from, std::int64_t count) {
  if (count > 0) std::memcpy(to, from, static_cast<std::size_t>(count) * sizeof(T));
}

template <class View>
std::int64_t extent(const View& v) {
  return static_cast<std::int64_t>(v.extent(0));
}

SegmentSizes sizes_of(const OwnerPart& p, std::int64_t pieces, int iterations) {
  SegmentSizes s;
  s.vertices = extent(p.base);
  s.map_colors = extent(p.prev);
  s.halo_colors = extent(p.sparse.halo);
  s.cached_hits = extent(p.cache);
  s.traced_hits = extent(p.traced);
  s.sparse = p.sparse.empty() ? 0 : 1;
  s.sparse_map_colors = p.sparse.map_colors;
  s.mask_words = extent(p.sparse.mask);
  s.kept_words = extent(p.sparse.kept);
  s.pieces = pieces;
  s.iterations = iterations + 1;
  return s;
}

}  // namespace

std::size_t NodeShare::carve(char* at, const SegmentSizes& s, Segment* out) {
  Carver c(at);
  Segment seg;
  c.take<SegmentSizes>(1);
  seg.counters = c.take<PaddedCounter>(s.iterations);
  seg.pieces = c.take<TracePiece>(s.pieces);
  seg.base = c.take<Vec3>(s.vertices);
  seg.map_offset = c.take<std::int64_t>(s.vertices + 1);
  seg.start = c.take<std::int64_t>(s.sparse ? s.vertices : 0);
  seg.mask_at = c.take<std::int64_t>(s.sparse ? s.vertices : 0);
  seg.mask = c.take<std::uint64_t>(s.mask_words);
  seg.kept = c.take<std::int32_t>(s.kept_words);
  seg.cached = c.take<CachedHit>(s.cached_hits);
  seg.traced = c.take<TracedHit>(s.traced_hits);
  seg.buffer[0] = c.take<Vec3f>(s.map_colors);
  seg.buffer[1] = c.take<Vec3f>(s.map_colors);
  seg.halo = c.take<Vec3f>(s.halo_colors);
  seg.sizes = s;
  if (out) *out = seg;
  return c.used();
}

#ifdef RTMINI_HAVE_MPI

NodeShare::NodeShare(const Communicator& comm, const OwnerPart& mine,
                     const std::vector<TracePiece>& pieces, int first_iteration, int iterations)
    : first_iteration_(first_iteration) {
  const SegmentSizes sizes = sizes_of(mine, static_cast<std::int64_t>(pieces.size()), iterations);
  my_bytes_ = static_cast<std::int64_t>(carve(nullptr, sizes, nullptr));
  // Every rank is alive here (a failed peer ends this barrier with PeerFailure): the blocking
  // window calls below cannot wait on a rank that has gone.
  comm.barrier();
  MPI_Comm_split_type(comm.native(), MPI_COMM_TYPE_SHARED, comm.rank(), MPI_INFO_NULL, &node_);
  MPI_Comm_set_errhandler(node_, MPI_ERRORS_RETURN);
  int size = 1;
  MPI_Comm_rank(node_, &node_rank_);
  MPI_Comm_size(node_, &size);
  MPI_Info info = MPI_INFO_NULL;
  MPI_Info_create(&info);
  // Each rank's segment on its own pages, first touched (below) by the rank that computes it.
  MPI_Info_set(info, "alloc_shared_noncontig", "true");
  char* mine_at = nullptr;
  const int rc = MPI_Win_allocate_shared(static_cast<MPI_Aint>(my_bytes_), 1, info, node_,
                                         &mine_at, &win_);
  MPI_Info_free(&info);
  if (rc != MPI_SUCCESS)
    throw IoError("bake --node-sharing: an MPI shared-memory window of " +
                  std::to_string(my_bytes_) +
                  " bytes could not be allocated (is the node's shared memory, e.g. /dev/shm, "
                  "large enough?)");
  MPI_Win_lock_all(MPI_MODE_NOCHECK, win_);

  Segment seg;
  carve(mine_at, sizes, &seg);
  std::memcpy(mine_at, &sizes, sizeof sizes);
  for (std::int64_t i = 0; i < sizes.iterations; ++i) {
    new (&seg.counters[i]) PaddedCounter;
    seg.counters[i].value.store(0);
  }
  copy_into(seg.pieces, pieces.data(), sizes.pieces);
  copy_into(seg.base, mine.base.data(), sizes.vertices);
  copy_into(seg.map_offset, mine.map_offset.data(), sizes.vertices + 1);
  if (sizes.sparse) {
    copy_into(seg.start, mine.sparse.start.data(), sizes.vertices);
    copy_into(seg.mask_at, mine.sparse.mask_at.data(), sizes.vertices);
  }
  copy_into(seg.mask, mine.sparse.mask.data(), sizes.mask_words);
  copy_into(seg.kept, mine.sparse.kept.data(), sizes.kept_words);
  copy_into(seg.cached, mine.cache.data(), sizes.cached_hits);
  copy_into(seg.traced, mine.traced.data(), sizes.traced_hits);
  copy_into(seg.buffer[0], mine.prev.data(), sizes.map_colors);
  copy_into(seg.buffer[1], mine.next.data(), sizes.map_colors);
  copy_into(seg.halo, mine.sparse.halo.data(), sizes.halo_colors);

  // Every segment is complete before anyone reads another's sizes.
  node_barrier(comm);
  segments_.resize(static_cast<std::size_t>(size));
  for (int r = 0; r < size; ++r) {
    MPI_Aint bytes = 0;
    int disp = 1;
    char* at = nullptr;
    MPI_Win_shared_query(win_, r, &bytes, &disp, &at);
    SegmentSizes s;
    std::memcpy(&s, at, sizeof s);
    carve(at, s, &segments_[static_cast<std::size_t>(r)]);
  }
}

NodeShare::~NodeShare() {
  // Not MPI_Win_free: it is collective, and a destructor may run on one rank's error path while
  // the others wait elsewhere (they would hang). The window goes with MPI_Finalize.
  if (win_ != MPI_WIN_NULL) MPI_Win_unlock_all(win_);
}

void NodeShare::node_barrier(const Communicator& comm) const {
  MPI_Win_sync(win_);  // this rank's writes to the window are visible ...
  MPI_Request req = MPI_REQUEST_NULL;
  MPI_Ibarrier(node_, &req);
  comm.wait(req);      // ... once every rank of the node has made them so (or a peer failed)
  MPI_Win_sync(win_);  // and this rank sees theirs
}

#else

NodeShare::NodeShare(const Communicator&, const OwnerPart&, const std::vector<TracePiece>&, int,
                     int) {
  throw InputError("bake --node-sharing needs a build with MPI");
}
NodeShare::~NodeShare() = default;
void NodeShare::node_barrier(const Communicator&) const {}

#endif

std::int64_t NodeShare::claim(int r, int it) const {
  const Segment& s = segments_[static_cast<std::size_t>(r)];
  const std::int64_t i = s.counters[it].value.fetch_add(1, std::memory_order_relaxed);
  return i < s.sizes.pieces ? i : -1;
}

Kokkos::View<Vec3f*, MemSpace> NodeShare::halo() const {
  const Segment& s = segments_[static_cast<std::size_t>(node_rank_)];
  return Kokkos::View<Vec3f*, MemSpace>(s.halo, static_cast<std::size_t>(s.sizes.halo_colors));
}

OwnerPart NodeShare::part(int r, int it) const {
  const Segment& s = segments_[static_cast<std::size_t>(r)];
  const SegmentSizes& n = s.sizes;
  const auto count = [](std::int64_t c) { return static_cast<std::size_t>(c); };
  OwnerPart p;
  p.base = Kokkos::View<Vec3*, MemSpace>(s.base, count(n.vertices));
  p.map_offset = Kokkos::View<std::int64_t*, MemSpace>(s.map_offset, count(n.vertices + 1));
  p.cache = Kokkos::View<CachedHit*, MemSpace>(s.cached, count(n.cached_hits));
  p.traced = Kokkos::View<TracedHit*, MemSpace>(s.traced, count(n.traced_hits));
  const int which = (it - first_iteration_) % 2;
  p.prev = Kokkos::View<Vec3f*, MemSpace>(s.buffer[which], count(n.map_colors));
  p.next = Kokkos::View<Vec3f*, MemSpace>(s.buffer[1 - which], count(n.map_colors));
  if (n.sparse) {
    p.sparse.start = Kokkos::View<const std::int64_t*, MemSpace>(s.start, count(n.vertices));
    p.sparse.mask_at = Kokkos::View<const std::int64_t*, MemSpace>(s.mask_at, count(n.vertices));
    p.sparse.mask = Kokkos::View<const std::uint64_t*, MemSpace>(s.mask, count(n.mask_words));
    p.sparse.kept = Kokkos::View<const std::int32_t*, MemSpace>(s.kept, count(n.kept_words));
    p.sparse.map_colors = n.sparse_map_colors;
    p.sparse.halo = Kokkos::View<const Vec3f*, MemSpace>(s.halo, count(n.halo_colors));
  }
  return p;
}

}  // namespace rtmini::bake
