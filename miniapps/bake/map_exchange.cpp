#include "map_exchange.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#if defined(RTMINI_HAVE_MPI) && defined(OPEN_MPI) && __has_include(<mpi-ext.h>)
#include <mpi-ext.h>  // MPIX_Query_cuda_support
#endif

namespace rtmini::bake {
namespace {

using Exec = Kokkos::DefaultExecutionSpace;
using Policy = Kokkos::RangePolicy<Exec, Kokkos::IndexType<std::int64_t>>;

int checked_int(std::int64_t n) {
  if (n > 2147483647) throw std::runtime_error("rtmini: a map exchange exceeds 2^31 entries");
  return static_cast<int>(n);
}

// MPI's displacements are ints: summed in 64 bits so an oversized exchange fails loudly
// instead of wrapping around.
std::vector<int> displacements(const std::vector<int>& counts) {
  std::vector<int> d(counts.size(), 0);
  std::int64_t sum = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    d[r] = checked_int(sum);
    sum += counts[r];
  }
  checked_int(sum);
  return d;
}

#ifdef RTMINI_HAVE_MPI
constexpr int kExchangeTag = 23;  // the exchanges' point-to-point messages on the bake's comm

// One step of a pairwise exchange: `bytes_out` to rank `to`, `bytes_in` from rank `from` (either
// may be zero), both waited for; `owned` as Communicator::wait_keeping keeps them.
template <class... Owned>
void exchange_with(const Communicator& comm, const unsigned char* out, std::int64_t bytes_out,
                   int to, unsigned char* in, std::int64_t bytes_in, int from, MPI_Datatype type,
                   std::int64_t record_bytes, Owned&... owned) {
  MPI_Request recv = MPI_REQUEST_NULL, send = MPI_REQUEST_NULL;
  if (bytes_in > 0)
    MPI_Irecv(in, checked_int(bytes_in / record_bytes), type, from, kExchangeTag, comm.native(),
              &recv);
  if (bytes_out > 0)
    MPI_Isend(out, checked_int(bytes_out / record_bytes), type, to, kExchangeTag, comm.native(),
              &send);
  if (recv != MPI_REQUEST_NULL) comm.wait_keeping(recv, owned...);
  if (send != MPI_REQUEST_NULL) comm.wait_keeping(send, owned...);
}
#endif

// MPI_Alltoallv's result for records of record_bytes each, counts in records (so a large
// exchange counts records, not bytes, in MPI's ints). `send` and `recv` own the buffers
// (std::vector or a managed Kokkos::View; moved from only when a peer fails): non-blocking plus
// Communicator::wait_keeping, so a rank that failed elsewhere cannot leave the others waiting here
// forever (the collective-failure contract, docs/architecture.md), and the messages it abandons
// keep their buffers and counts, which MPI's progress engine may still touch while the ranks agree
// on the exit code (freed under it, they crashed that agreement: commit 23bae46).
// `recv_displs`: where each rank's records land in `recv` (empty: one after the other).
//
// Pairwise, not MPI_Ialltoallv: in step s a rank sends to rank + s and receives from rank - s,
// one peer each way at a time. With every message in flight at once (MPI_Ialltoallv), Open MPI's
// shared-memory transport filled fragments for every peer, and each rank's resident set held
// about 1 MiB of shared memory per peer on its node (results/bake/distributed.md, seventeenth
// round).
template <class Send, class Recv>
void alltoallv_records(const Communicator& comm, Send& send, const std::vector<int>& send_counts,
                       Recv& recv, const std::vector<int>& recv_counts, std::size_t record_bytes,
                       const std::vector<int>& recv_displs = {}) {
  std::vector<int> sc = send_counts, rc = recv_counts;  // kept with the messages, as the buffers
  std::vector<int> sd = displacements(sc),
                   rd = recv_displs.empty() ? displacements(rc) : recv_displs;
  const auto* out = reinterpret_cast<const unsigned char*>(send.data());
  auto* in = reinterpret_cast<unsigned char*>(recv.data());
  const auto rb = static_cast<std::int64_t>(record_bytes);
  const int me = comm.rank(), p = comm.size();
#ifdef RTMINI_HAVE_MPI
  MPI_Datatype type;
  MPI_Type_contiguous(static_cast<int>(record_bytes), MPI_BYTE, &type);
  MPI_Type_commit(&type);
  // Step 0 is this rank's own records, through MPI too: the buffers may be device memory that
  // only a CUDA-aware MPI may touch (mpi_takes_map_memory).
  for (int s = 0; s < p; ++s) {
    const int to = (me + s) % p, from = (me - s + p) % p;
    exchange_with(comm, out + sd[to] * rb, sc[to] * rb, to, in + rd[from] * rb, rc[from] * rb, from,
                  type, rb, send, recv, sc, sd, rc, rd);
  }
  MPI_Type_free(&type);  // an abandoned exchange keeps `type` too
#else
  std::copy_n(out + sd[me] * rb, sc[me] * rb, in + rd[me] * rb);
  (void)p;
#endif
}

// The all-to-all exchange of the elements of `send` into `recv` (containers of one trivially
// copyable type, owned as alltoallv_records says), counts in elements.
template <class Send, class Recv>
void alltoallv(const Communicator& comm, Send& send, const std::vector<int>& send_counts,
               Recv& recv, const std::vector<int>& recv_counts) {
  using T = std::remove_reference_t<decltype(*send.data())>;
  static_assert(std::is_same<T, std::remove_reference_t<decltype(*recv.data())>>::value,
                "an exchange sends and receives one type");
  alltoallv_records(comm, send, send_counts, recv, recv_counts, sizeof(T));
}

std::vector<int> exchange_counts(const Communicator& comm, const std::vector<int>& send_counts) {
  std::vector<int> send = send_counts, recv(send_counts.size(), 0);
  const std::vector<int> ones(send_counts.size(), 1);
  alltoallv(comm, send, ones, recv, ones);
  return recv;
}

Kokkos::View<std::int64_t*, MemSpace> upload(const char* label,
                                             const std::vector<std::int64_t>& v) {
  return compat::upload<MemSpace>(label, v);
}

// The vertex that global colour entry g belongs to.
std::int64_t vertex_of_entry(const BakeSceneHost& scene, std::int64_t g) {
  const auto& off = scene.color_offset;
  return std::upper_bound(off.begin(), off.end(), g) - off.begin() - 1;
}

// f(i) for i in [0, n) on the host threads. The exchange is planned on the host, per vertex or
// per halo entry, independently; on one thread, a rank of 8 (2 x 8 on the 16-core host) spent
// 0.13 s on its first exchange, mostly this plan, against 0.72 s per iteration.
template <class F>
void host_parallel_for(const char* label, std::int64_t n, const F& f) {
  using Host = Kokkos::DefaultHostExecutionSpace;
  Kokkos::parallel_for(label, Kokkos::RangePolicy<Host, Kokkos::IndexType<std::int64_t>>(0, n), f);
  Host().fence();
}

// Global colour entries turned, in place, into `layout`'s entries of the same colours. The lists
// planned here are ascending (per owner), so each piece of them searches its first vertex and
// then walks the offsets, instead of a binary search over all vertices per entry.
void to_layout_entries(const BakeSceneHost& scene, const MapLayout& layout, std::int64_t* entries,
                       std::int64_t n) {
  constexpr std::int64_t kPiece = 4096, kWalk = 16;
  const auto& off = scene.color_offset;
  host_parallel_for(
      "rtmini::bake::exchange_entries", (n + kPiece - 1) / kPiece, [&](std::int64_t piece) {
        std::int64_t v = -1;
        for (std::int64_t k = piece * kPiece; k < std::min(n, (piece + 1) * kPiece); ++k) {
          const std::int64_t g = entries[k];
          for (std::int64_t step = 0; v >= 0 && step < kWalk && off[v + 1] <= g; ++step) ++v;
          if (v < 0 || g < off[v] || off[v + 1] <= g) v = vertex_of_entry(scene, g);
          entries[k] = layout.entry(v, g - off[v]);
        }
      });
}

}  // namespace

bool mpi_takes_map_memory() {
  if (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible) return true;
  if (const char* e = std::getenv("RTMINI_MPI_DEVICE_BUFFERS"); e && std::string(e) == "0")
    return false;
#if defined(MPIX_CUDA_AWARE_SUPPORT) && MPIX_CUDA_AWARE_SUPPORT
  return MPIX_Query_cuda_support() == 1;
#else
  return false;
#endif
}

namespace {
template <class T>
std::int64_t bytes_of(const std::vector<T>& v) {
  return static_cast<std::int64_t>(v.capacity() * sizeof(T));
}
template <class V>
std::int64_t view_bytes(const V& v) {
  return static_cast<std::int64_t>(v.span() * sizeof(typename V::value_type));
}
// A device copy's bytes, unless it shares the host vector's memory.
template <class V, class T>
std::int64_t copy_bytes(const V& device, const std::vector<T>& host) {
  return static_cast<const void*>(device.data()) == static_cast<const void*>(host.data())
             ? 0
             : view_bytes(device);
}
}  // namespace

std::int64_t MapLayout::table_bytes() const {
  std::int64_t b = bytes_of(offset) + bytes_of(halo_at) + bytes_of(halo_rank_at) +
                   bytes_of(mask_at) + bytes_of(mask) + bytes_of(kept) + copy_bytes(device, offset);
  return b + view_bytes(sparse.span) + copy_bytes(sparse.mask, mask) +
         copy_bytes(sparse.kept, kept);
}

std::int64_t MapExchange::send_list_bytes() const {
  return view_bytes(send_items_) + view_bytes(first_entry_);
}

std::int64_t MapExchange::scratch_bytes() const {
  return view_bytes(changed_bits_) + view_bytes(changed_words_before_) + view_bytes(message_words_);
}

namespace {
// Where the Chef reads a layout's table `v`: the host vector itself on a host backend (an
// unmanaged view, valid while the MapLayout, moved but never copied, holds the vector), else a
// device copy. The copies were 2 MiB of the largest 16 x 1 rank's peak on bunny_room
// (results/bake/distributed.md, fifteenth round).
template <class T>
Kokkos::View<T*, MemSpace> device_table(const char* label, std::vector<T>& v) {
  if (Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemSpace>::accessible)
    return Kokkos::View<T*, MemSpace>(v.data(), v.size());
  return compat::upload<MemSpace>(label, v);
}

// Every vertex's ColorSpan: its first entry (`first`), the scene's colour count and its first
// mask word (-1: dense).
template <class First>
Kokkos::View<const ColorSpan*, MemSpace> color_spans(const BakeSceneHost& scene,
                                                     const std::vector<std::int64_t>& mask_at,
                                                     const First& first) {
  std::vector<ColorSpan> span(static_cast<std::size_t>(scene.vertices()));
  for (std::int64_t v = 0; v < scene.vertices(); ++v)
    span[v] = {first(v), static_cast<std::int32_t>(scene.color_count(v)),
               static_cast<std::int32_t>(mask_at[v])};
  return compat::upload<MemSpace>("rtmini::bake::map_spans", span);
}
}  // namespace

MapLayout make_map_layout(const BakeSceneHost& scene, const std::vector<char>& present) {
  MapLayout l;
  const std::int64_t nv = scene.vertices();
  l.offset.assign(static_cast<std::size_t>(nv) + 1, 0);
  for (std::int64_t v = 0; v < nv; ++v)
    l.offset[v + 1] = l.offset[v] + (present[v] ? scene.color_count(v) : 0);
  l.device = device_table("rtmini::bake::map_offset", l.offset);
  return l;
}

MapLayout make_halo_layout(const BakeSceneHost& scene, const MapLayout& remote, const char* read,
                           const std::vector<int>& owner, const std::vector<char>& own) {
  const std::int64_t nv = scene.vertices();
  MapLayout l = make_map_layout(scene, own);
  const auto held = [&](std::int64_t v) { return !own[v] && remote.in_map(v); };
  const auto sparse = [&](std::int64_t v) { return read && held(v) && scene.color_count(v) > 1; };
  // Mask words first (64 viewpoints each, per sparse vertex), then each vertex's words and kept
  // count independently, then the halo offsets in receive order.
  l.mask_at.assign(static_cast<std::size_t>(nv), -1);
  std::int64_t words = 0;
  for (std::int64_t v = 0; v < nv; ++v)
    if (sparse(v)) {
      l.mask_at[v] = words;
      words += (scene.color_count(v) + 63) / 64;
    }
  l.mask.assign(static_cast<std::size_t>(words), 0);
  l.kept.assign(static_cast<std::size_t>(words), 0);
  std::vector<std::int64_t> keep(static_cast<std::size_t>(nv), 0);
  host_parallel_for("rtmini::bake::halo_layout", nv, [&](std::int64_t v) {
    if (!held(v)) return;
    const std::int64_t n = scene.color_count(v);
    keep[v] = n;
    if (!sparse(v)) return;
    std::int64_t kept = 0;
    for (std::int64_t w = 0; w < (n + 63) / 64; ++w) {
      std::uint64_t bits = 0;
      for (std::int64_t j = w * 64; j < std::min(n, w * 64 + 64); ++j)
        if (read[remote.offset[v] + j]) bits |= std::uint64_t(1) << (j & 63);
      l.mask[l.mask_at[v] + w] = bits;
      l.kept[l.mask_at[v] + w] = static_cast<std::int32_t>(kept);
      kept += compat::popcount64(bits);
    }
    keep[v] = kept;
  });
  // Receive order: by owner rank (a counting sort of the held vertices), then by vertex.
  const int ranks = owner.empty() ? 1 : 1 + *std::max_element(owner.begin(), owner.end());
  std::vector<std::int64_t> rank_at(static_cast<std::size_t>(ranks) + 1, 0);
  for (std::int64_t v = 0; v < nv; ++v)
    if (held(v)) rank_at[owner[v] + 1] += keep[v];
  for (std::size_t r = 1; r < rank_at.size(); ++r) rank_at[r] += rank_at[r - 1];
  l.halo_rank_at = rank_at;
  l.halo_at.assign(static_cast<std::size_t>(nv), -1);
  for (std::int64_t v = 0; v < nv; ++v)
    if (held(v)) {
      l.halo_at[v] = rank_at[owner[v]];
      rank_at[owner[v]] += keep[v];
    }
  l.halo_colors = rank_at.back();
  // SparseColors: every vertex's first entry in the map-then-halo numbering.
  if (words > std::numeric_limits<std::int32_t>::max())
    throw std::length_error("bake: the halo's viewpoint masks exceed 2^31 words");
  l.sparse.span = color_spans(scene, l.mask_at, [&](std::int64_t v) {
    return l.in_halo(v) ? l.colors() + l.halo_at[v] : l.offset[v];
  });
  l.sparse.mask = device_table("rtmini::bake::map_mask", l.mask);
  l.sparse.kept = device_table("rtmini::bake::map_kept", l.kept);
  l.sparse.map_colors = l.colors();
  return l;
}

std::vector<std::int64_t> remote_entries(const BakeSceneHost& scene, const MapLayout& layout) {
  const std::int64_t nv = scene.vertices();
  std::vector<std::int64_t> halo(static_cast<std::size_t>(layout.halo_colors));
  host_parallel_for("rtmini::bake::remote_entries", nv, [&](std::int64_t v) {
    if (!layout.in_halo(v)) return;
    const std::int64_t first = scene.color_offset[v];
    std::int64_t k = layout.halo_at[v];
    if (layout.dense(v)) {
      for (std::int64_t j = 0; j < scene.color_count(v); ++j) halo[k++] = first + j;
      return;
    }
    const std::int64_t words = (scene.color_count(v) + 63) / 64;
    for (std::int64_t w = 0; w < words; ++w)
      for (std::uint64_t bits = layout.mask[layout.mask_at[v] + w]; bits != 0; bits &= bits - 1)
        halo[k++] = first + w * 64 + compat::popcount64((bits & (~bits + 1)) - 1);
  });
  return halo;
}

void mark_dense(const BakeSceneHost& scene, MapLayout& layout) {
  layout.mask_at.assign(static_cast<std::size_t>(scene.vertices()), -1);
  layout.sparse.span =
      color_spans(scene, layout.mask_at, [&](std::int64_t v) { return layout.offset[v]; });
  layout.sparse.map_colors = layout.colors();
}

std::vector<Vec3f> fetch_vertex_colors(const Communicator& comm, const std::vector<int>& owner,
                                       const std::vector<std::int64_t>& wanted,
                                       const std::vector<Vec3f>& own) {
  // Requests grouped by owner; slot[k]: where wanted[k] sits in that grouping.
  std::vector<int> ask(comm.size(), 0);
  for (const std::int64_t v : wanted) ++ask[owner[v]];
  std::vector<std::int64_t> asked(wanted.size());
  std::vector<std::size_t> slot(wanted.size());
  {
    std::vector<int> pos = displacements(ask);
    for (std::size_t k = 0; k < wanted.size(); ++k) {
      slot[k] = static_cast<std::size_t>(pos[owner[wanted[k]]]++);
      asked[slot[k]] = wanted[k];
    }
  }
  const std::vector<int> told = exchange_counts(comm, ask);
  std::int64_t requests = 0;
  for (const int n : told) requests += n;
  std::vector<std::int64_t> vertices(static_cast<std::size_t>(requests));
  alltoallv(comm, asked, ask, vertices, told);
  std::vector<Vec3f> answers(vertices.size());
  for (std::size_t k = 0; k < vertices.size(); ++k) answers[k] = own[vertices[k]];
  std::vector<Vec3f> grouped(wanted.size());
  alltoallv(comm, answers, told, grouped, ask);
  std::vector<Vec3f> out(wanted.size());
  for (std::size_t k = 0; k < wanted.size(); ++k) out[k] = grouped[slot[k]];
  return out;
}

MapExchange::MapExchange(const Communicator& comm, const BakeSceneHost& scene,
                         const MapLayout& layout, bool changed_only,
                         Kokkos::View<Vec3f*, MemSpace> halo_storage, bool map_shared)
    : changed_only_(changed_only), map_shared_(map_shared) {
  const int ranks = comm.size();
  // Requests: the halo entries, which are grouped by owner already (the halo's order). The
  // lists are built in place and freed as soon as they are used: at the plan's peak they were
  // four times the buffers the exchange keeps.
  std::vector<int> ask(ranks, 0);
  for (int r = 0; r < ranks && r + 1 < static_cast<int>(layout.halo_rank_at.size()); ++r)
    ask[r] = checked_int(layout.halo_rank_at[r + 1] - layout.halo_rank_at[r]);
  const std::vector<int> told = exchange_counts(comm, ask);
  const std::size_t sent = static_cast<std::size_t>(total(told));
  if (layout.colors() > std::int64_t(std::numeric_limits<SendItem>::max()))
    throw std::runtime_error("rtmini: a rank's map exceeds 2^32 entries");
  {
    // Global entry numbers asked (they may pass 2^32), turned into this rank's map entries.
    std::vector<std::int64_t> send(sent);
    {
      std::vector<std::int64_t> asked = remote_entries(scene, layout);
      alltoallv(comm, asked, ask, send, told);
    }
    // What this rank sends: its own entries that each asker wants; what it gets lands in the halo.
    to_layout_entries(scene, layout, send.data(), static_cast<std::int64_t>(sent));
    send_items_ = Kokkos::View<SendItem*, MemSpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::exchange_send_items"), sent);
    auto items = Kokkos::create_mirror_view(send_items_);  // send_items_ itself on a host backend
    host_parallel_for("rtmini::bake::exchange_send_items", static_cast<std::int64_t>(sent),
                      [&](std::int64_t i) { items(i) = static_cast<SendItem>(send[i]); });
    Kokkos::deep_copy(send_items_, items);
  }
  send_counts_ = told;
  recv_counts_ = ask;
  send_displs_ = displacements(send_counts_);
  recv_displs_ = displacements(recv_counts_);
  const std::size_t received = static_cast<std::size_t>(total(ask));
  std::vector<std::int64_t> first_entry(send_displs_.begin(), send_displs_.end());
  first_entry.push_back(static_cast<std::int64_t>(sent));
  first_entry_ = upload("rtmini::bake::exchange_first_entry", first_entry);
  recv_buf_ = halo_storage.data() ? halo_storage
                                  : Kokkos::View<Vec3f*, MemSpace>("rtmini::bake::halo", received);
  if (recv_buf_.extent(0) != received)
    throw std::logic_error("bake: the halo's storage does not match the exchange's plan");
  direct_ = mpi_takes_map_memory();
}

std::int64_t MapExchange::run(const Communicator& comm, Kokkos::View<Vec3f*, MemSpace> map,
                              Kokkos::View<Vec3f*, MemSpace> other) {
  if (comm.size() == 1) return 0;
  const Kokkos::View<Vec3f*, MemSpace> scratch =
      map_shared_ ? Kokkos::View<Vec3f*, MemSpace>() : other;
  const std::int64_t bytes = sent_ && changed_only_ ? run_changed(comm, map, other, scratch)
                                                     : run_full(comm, map, scratch);
  sent_ = true;
  Kokkos::fence();
  return bytes;
}

namespace {

// The records to each peer in `round` of `rounds`: an equal share of its `count`, rounded up (the
// last rounds may hold fewer or none). Sender and receiver derive the same from the count.
std::vector<int> round_counts(const std::vector<int>& count, std::int64_t round,
                              std::int64_t rounds) {
  std::vector<int> out(count.size());
  for (std::size_t r = 0; r < count.size(); ++r) {
    const std::int64_t share = (count[r] + rounds - 1) / rounds;
    out[r] = static_cast<int>(std::max<std::int64_t>(
        0, std::min<std::int64_t>(count[r], share * (round + 1)) - share * round));
  }
  return out;
}

}  // namespace

// The first exchange sends every halo colour. They are packed into `spare`, the other map
// buffer: its colours (the iteration before's, or the restart's) are read by no one before the
// next iteration overwrites every entry, and a changed-only run compares with the map just sent,
// not with these. A rank that sends more colours than it owns sends them in rounds, an equal
// share of every peer's list per round, as many rounds as the rank that needs most (its packed
// colours were a third buffer of 12 bytes per colour sent, about 9 MB of the 16 x 1 ranks'
// ~30 MB step at iteration 1 on bunny_room, results/bake/distributed.md, thirteenth round).
std::int64_t MapExchange::run_full(const Communicator& comm, Kokkos::View<Vec3f*, MemSpace> map,
                                   Kokkos::View<Vec3f*, MemSpace> spare) {
  const std::int64_t sent = send_colors(), room = static_cast<std::int64_t>(spare.extent(0));
  const std::int64_t ranks = comm.size();
  auto send_items = send_items_;
  // With R rounds a round packs at most sent / R + ranks colours (one rounded up per peer).
  std::int64_t rounds = 1;
  if (sent > room && room > ranks) rounds = (sent + room - ranks - 1) / (room - ranks);
  rounds = static_cast<std::int64_t>(comm.max(static_cast<double>(rounds)));
  std::int64_t most = 0;  // the largest round this rank packs: its first
  for (const int n : round_counts(send_counts_, 0, rounds)) most += n;
  Kokkos::View<Vec3f*, MemSpace> packed = spare;
  if (most > room)  // a rank of (almost) no colours read by many: a buffer of its own
    packed = Kokkos::View<Vec3f*, MemSpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::exchange_send"),
        static_cast<std::size_t>(most));
  std::vector<Vec3f> host_recv(direct_ ? 0 : recv_buf_.extent(0));  // staging, without direct_
  std::vector<int> recv_at = recv_displs_;  // where each peer's next colours land in the halo
  std::vector<std::int64_t> send_at(send_displs_.begin(), send_displs_.end());
  for (std::int64_t round = 0; round < rounds; ++round) {
    const std::vector<int> sc = round_counts(send_counts_, round, rounds);
    const std::vector<int> rc = round_counts(recv_counts_, round, rounds);
    std::int64_t n = 0;
    for (std::int64_t r = 0; r < ranks; ++r) {
      const std::int64_t to = n, from = send_at[r];
      Kokkos::parallel_for(
          "rtmini::bake::exchange_pack", Policy(0, sc[r]),
          KOKKOS_LAMBDA(std::int64_t i) { packed(to + i) = map(send_items(from + i)); });
      n += sc[r];
      send_at[r] += sc[r];
    }
    if (direct_) {
      Kokkos::fence();  // the packed colours must be in memory before MPI reads them
      alltoallv_records(comm, packed, sc, recv_buf_, rc, sizeof(Vec3f), recv_at);
    } else {
      // Device memory and an MPI that cannot read it: through host buffers (any MPI works).
      std::vector<Vec3f> host_send(static_cast<std::size_t>(n));
      Kokkos::deep_copy(compat::host_view(host_send.data(), host_send.size()),
                        Kokkos::subview(packed, std::make_pair(std::int64_t(0), n)));
      alltoallv_records(comm, host_send, sc, host_recv, rc, sizeof(Vec3f), recv_at);
    }
    for (std::int64_t r = 0; r < ranks; ++r) recv_at[r] += rc[r];
  }
  if (!direct_) Kokkos::deep_copy(recv_buf_, compat::host_view(host_recv.data(), host_recv.size()));
  return sent * static_cast<std::int64_t>(sizeof(Vec3f));
}

namespace {

// A changed-only message of `changed` colours among `entries`: an index list (one word a colour)
// when that is no longer than a bitmask (one bit an entry), then three words a colour. Sender and
// receiver both derive it from the two counts, so only the count travels ahead.
bool index_list(std::int64_t changed, std::int64_t entries) {
  return changed <= (entries + 31) / 32;
}
std::int64_t where_words(std::int64_t changed, std::int64_t entries) {
  return index_list(changed, entries) ? changed : (entries + 31) / 32;
}
std::int64_t message_words(std::int64_t changed, std::int64_t entries) {
  return changed == 0 ? 0 : where_words(changed, entries) + 3 * changed;
}

KOKKOS_INLINE_FUNCTION bool same_bits(const Vec3f& a, const Vec3f& b) {
  return compat::bit_cast<std::uint32_t>(a.x) == compat::bit_cast<std::uint32_t>(b.x) &&
         compat::bit_cast<std::uint32_t>(a.y) == compat::bit_cast<std::uint32_t>(b.y) &&
         compat::bit_cast<std::uint32_t>(a.z) == compat::bit_cast<std::uint32_t>(b.z);
}

using Words = Kokkos::View<std::uint32_t*, MemSpace>;
// Words in memory that another view owns (a message in the previous map's memory).
using WordsAt = Kokkos::View<std::uint32_t*, MemSpace, Kokkos::MemoryUnmanaged>;

// Per destination of a changed-only exchange: where its message starts (words), its first
// changed colour and first entry in send order, where its colours start (words) and whether it
// is an index list (else a bitmask).
enum MessageField { kFirstWord, kFirstChanged, kFirstEntry, kColorsAt, kIndexList, kMessageFields };

KOKKOS_INLINE_FUNCTION void put_color(const WordsAt& w, std::int64_t at, const Vec3f& c) {
  w(at) = compat::bit_cast<std::uint32_t>(c.x);
  w(at + 1) = compat::bit_cast<std::uint32_t>(c.y);
  w(at + 2) = compat::bit_cast<std::uint32_t>(c.z);
}
KOKKOS_INLINE_FUNCTION Vec3f get_color(const WordsAt& w, std::int64_t at) {
  return Vec3f(compat::bit_cast<float>(w(at)), compat::bit_cast<float>(w(at + 1)),
               compat::bit_cast<float>(w(at + 2)));
}

// The rank that send entry i goes to: the last whose first entry is at or before i (the ranks'
// entries are consecutive, in rank order; a rank sent nothing starts where the next one does).
KOKKOS_INLINE_FUNCTION int destination(const Kokkos::View<std::int64_t*, MemSpace>& first_entry,
                                       int ranks, std::int64_t i) {
  int lo = 0, hi = ranks - 1;
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (first_entry(mid) <= i)
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

// `words` if it holds n, else a new one of n (not zero-filled: every word sent is written).
Words words_for(const Words& words, std::int64_t n, const char* label) {
  if (static_cast<std::int64_t>(words.extent(0)) >= n) return words;
  return Words(Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string(label)),
               static_cast<std::size_t>(n));
}

// An exchange's message words at `at`, holding the views whose memory they are in: what
// alltoallv_records keeps alive when a peer fails while they are in flight.
struct MessageBuffer {
  Kokkos::View<Vec3f*, MemSpace> map;  // the previous map, when the words are in its memory
  Words own;                           // else the exchange's own buffer
  std::uint32_t* at = nullptr;
  std::uint32_t* data() const { return at; }
};

// Whether send entry i changed: bit i % 32 of word i / 32.
KOKKOS_INLINE_FUNCTION bool changed_entry(const Words& bits, std::int64_t i) {
  return ((bits(i >> 5) >> (i & 31)) & 1u) != 0;
}
// The changed entries before send entry i (i up to all of them): those of the words before its
// word, then its word's bits below it.
KOKKOS_INLINE_FUNCTION std::int64_t changed_before(
    const Words& bits, const Kokkos::View<std::int32_t*, MemSpace>& before, std::int64_t i) {
  const std::int64_t w = i >> 5;
  if ((i & 31) == 0) return before(w);
  return before(w) + compat::popcount64(bits(w) & ((std::uint32_t(1) << (i & 31)) - 1));
}

}  // namespace

std::int64_t MapExchange::run_changed(const Communicator& comm, Kokkos::View<Vec3f*, MemSpace> map,
                                      Kokkos::View<Vec3f*, MemSpace> previous,
                                      Kokkos::View<Vec3f*, MemSpace> scratch) {
  const int ranks = comm.size();
  const std::int64_t n = static_cast<std::int64_t>(send_items_.extent(0));
  const std::int64_t bit_words = mask_words(n);
  auto send_items = send_items_;
  auto first_entry = first_entry_;
  // (The counts have bit_words + 1 entries: a rank that sends nothing still scans one.)
  if (static_cast<std::int64_t>(changed_words_before_.extent(0)) != bit_words + 1) {
    changed_bits_ = Words(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::exchange_changed_bits"),
        static_cast<std::size_t>(bit_words));
    changed_words_before_ = Kokkos::View<std::int32_t*, MemSpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::exchange_changed_before"),
        static_cast<std::size_t>(bit_words) + 1);
  }
  auto bits = changed_bits_;
  auto before = changed_words_before_;
  // Bit i: whether entry i's colour changed since the last send (bit for bit: the receiver must
  // end with the sender's bits), which sent the previous iteration's map; then, per word, the
  // changed entries before it. A bit per entry and a count per 32 (a quarter byte an entry sent)
  // instead of a scanned count per entry (4 bytes): 3 MiB of the largest 16 x 1 rank's peak on
  // bunny_room (results/bake/distributed.md, fifteenth round).
  Kokkos::parallel_for(
      "rtmini::bake::exchange_changed", Policy(0, bit_words), KOKKOS_LAMBDA(std::int64_t w) {
        std::uint32_t b = 0;
        for (std::int64_t i = 32 * w; i < 32 * w + 32 && i < n; ++i)
          if (!same_bits(map(send_items(i)), previous(send_items(i))))
            b |= std::uint32_t(1) << (i & 31);
        bits(w) = b;
      });
  Kokkos::parallel_scan(
      "rtmini::bake::exchange_changed_scan", Policy(0, bit_words + 1),
      KOKKOS_LAMBDA(std::int64_t w, std::int32_t & sum, bool final) {
        if (final) before(w) = sum;
        if (w < bit_words) sum += static_cast<std::int32_t>(compat::popcount64(bits(w)));
      });
  // Per destination: the colours changed, the message's words and where its parts start.
  std::vector<std::int32_t> at;  // changed colours before each destination's first entry
  {
    Kokkos::View<std::int32_t*, MemSpace> bounds("rtmini::bake::exchange_changed_bounds",
                                                 static_cast<std::size_t>(ranks) + 1);
    Kokkos::parallel_for(
        "rtmini::bake::exchange_changed_bounds", Policy(0, ranks + 1),
        KOKKOS_LAMBDA(std::int64_t r) {
          bounds(r) = static_cast<std::int32_t>(changed_before(bits, before, first_entry(r)));
        });
    compat::download(bounds, at);
  }
  std::vector<int> changed(ranks), words(ranks);
  std::vector<std::int64_t> meta(kMessageFields * static_cast<std::size_t>(ranks));
  std::int64_t offset = 0;
  for (int r = 0; r < ranks; ++r) {
    const std::int64_t first = at[r], entries = send_counts_[r];
    changed[r] = static_cast<int>(at[r + 1] - first);
    words[r] = checked_int(message_words(changed[r], entries));
    std::int64_t* m = &meta[kMessageFields * static_cast<std::size_t>(r)];
    m[kFirstWord] = offset;
    m[kFirstChanged] = first;
    m[kFirstEntry] = send_displs_[r];
    m[kColorsAt] = offset + where_words(changed[r], entries);
    m[kIndexList] = index_list(changed[r], entries) ? 1 : 0;
    offset += words[r];
  }
  // The counts go ahead (each side derives a message's words from its count and entries).
  const std::vector<int> received = exchange_counts(comm, changed);
  std::vector<int> recv_words(ranks);
  std::int64_t recv_total = 0;
  for (int r = 0; r < ranks; ++r) {
    recv_words[r] = checked_int(message_words(received[r], recv_counts_[r]));
    recv_total += recv_words[r];
  }
  // The messages sent and received, one after the other: in the previous map's memory (scratch)
  // where they fit (read above for the last time; the next iteration overwrites all of it), else
  // in a buffer of the exchange's own (kept from run to run). Their own buffer was 4 MiB of the
  // largest 16 x 1 rank's peak on bunny_room.
  MessageBuffer send_buf, recv_buf_words;
  std::uint32_t* words_at = nullptr;
  if (offset + recv_total <= 3 * static_cast<std::int64_t>(scratch.extent(0))) {
    send_buf.map = recv_buf_words.map = scratch;
    words_at = reinterpret_cast<std::uint32_t*>(scratch.data());
  } else {
    message_words_ =
        words_for(message_words_, offset + recv_total, "rtmini::bake::exchange_message_words");
    send_buf.own = recv_buf_words.own = message_words_;
    words_at = message_words_.data();
  }
  send_buf.at = words_at;
  recv_buf_words.at = words_at + offset;
  const WordsAt send_words(send_buf.at, static_cast<std::size_t>(offset));
  const WordsAt recv_msg(recv_buf_words.at, static_cast<std::size_t>(recv_total));
  const auto message = upload("rtmini::bake::exchange_messages", meta);
  // The changed colours and an index list's indices...
  Kokkos::parallel_for(
      "rtmini::bake::exchange_pack_changed", Policy(0, n), KOKKOS_LAMBDA(std::int64_t i) {
        if (!changed_entry(bits, i)) return;
        const std::int64_t* m = &message(kMessageFields * destination(first_entry, ranks, i));
        const std::int64_t k = changed_before(bits, before, i) - m[kFirstChanged];
        put_color(send_words, m[kColorsAt] + 3 * k, map(send_items(i)));
        if (m[kIndexList])
          send_words(m[kFirstWord] + k) = static_cast<std::uint32_t>(i - m[kFirstEntry]);
      });
  // ... a bitmask's words, 32 entries each.
  for (int r = 0; r < ranks; ++r) {
    const std::int64_t* m = &meta[kMessageFields * static_cast<std::size_t>(r)];
    if (changed[r] == 0 || m[kIndexList]) continue;
    const std::int64_t first = m[kFirstEntry], end = first + send_counts_[r], w0 = m[kFirstWord];
    Kokkos::parallel_for(
        "rtmini::bake::exchange_pack_mask", Policy(0, mask_words(send_counts_[r])),
        KOKKOS_LAMBDA(std::int64_t w) {
          std::uint32_t b = 0;
          for (std::int64_t k = 0; k < 32 && first + 32 * w + k < end; ++k)
            if (changed_entry(bits, first + 32 * w + k)) b |= std::uint32_t(1) << k;
          send_words(w0 + w) = b;
        });
  }
  if (direct_) {
    Kokkos::fence();  // the packed words must be in memory before MPI reads them
    alltoallv_records(comm, send_buf, words, recv_buf_words, recv_words, sizeof(std::uint32_t));
  } else {
    std::vector<std::uint32_t> host_send(static_cast<std::size_t>(offset)),
        host_recv(static_cast<std::size_t>(recv_total));
    Kokkos::deep_copy(compat::host_view(host_send.data(), host_send.size()), send_words);
    alltoallv(comm, host_send, words, host_recv, recv_words);
    Kokkos::deep_copy(recv_msg, compat::host_view(host_recv.data(), host_recv.size()));
  }
  // Each rank's changed colours into the last received ones.
  auto recv_buf = recv_buf_;
  std::int64_t first_word = 0;
  for (int r = 0; r < ranks; ++r) {
    const std::int64_t c = received[r], entries = recv_counts_[r], base = recv_displs_[r];
    const std::int64_t w0 = first_word, colors_at = w0 + where_words(c, entries);
    first_word += recv_words[r];
    if (c == 0) continue;
    if (index_list(c, entries)) {
      Kokkos::parallel_for(
          "rtmini::bake::exchange_unpack_list", Policy(0, c), KOKKOS_LAMBDA(std::int64_t k) {
            recv_buf(base + recv_msg(w0 + k)) = get_color(recv_msg, colors_at + 3 * k);
          });
    } else {
      // Per mask word: the colours of the words before it (a scan over words, 1/32 of the
      // entries), then its set bits in order.
      Kokkos::parallel_scan(
          "rtmini::bake::exchange_unpack_mask", Policy(0, mask_words(entries)),
          KOKKOS_LAMBDA(std::int64_t w, std::int64_t & k, bool final) {
            std::uint32_t b = recv_msg(w0 + w);
            if (final)
              for (std::int64_t kk = k; b != 0; b &= b - 1, ++kk)
                recv_buf(base + 32 * w + compat::popcount64((b & (~b + 1)) - 1)) =
                    get_color(recv_msg, colors_at + 3 * kk);
            k += compat::popcount64(recv_msg(w0 + w));
          });
    }
  }
  Kokkos::fence();  // the words in the previous map are read before the next iteration writes it
  changed_colors_ += total(changed);
  offered_colors_ += send_colors();
  // The words and the counts sent to other ranks.
  return 4 * (offset + ranks - 1);
}

void MapExchange::release() {
  send_items_ = {};
  recv_buf_ = {};
  first_entry_ = {};
  changed_bits_ = {};
  changed_words_before_ = {};
  message_words_ = {};
}

std::vector<Vec3f> gather_global_map(const Communicator& comm, const BakeSceneHost& scene,
                                     const MapLayout& layout, const Vec3f* local,
                                     const std::vector<int>& owner) {
  const std::int64_t nv = scene.vertices();
  std::vector<Vec3f> mine;
  for (std::int64_t v = 0; v < nv; ++v)
    if (owner[v] == comm.rank())
      mine.insert(mine.end(), local + layout.offset[v], local + layout.offset[v + 1]);
  if (comm.size() == 1) return mine;
  const std::vector<Vec3f> all = comm.gatherv(mine);
  if (!comm.is_root()) return {};
  // gatherv concatenates in rank order, each rank's vertices ascending.
  std::vector<std::int64_t> start(static_cast<std::size_t>(comm.size()) + 1, 0);
  for (std::int64_t v = 0; v < nv; ++v) start[owner[v] + 1] += scene.color_count(v);
  for (int r = 0; r < comm.size(); ++r) start[r + 1] += start[r];
  std::vector<Vec3f> global(static_cast<std::size_t>(scene.colors()));
  for (std::int64_t v = 0; v < nv; ++v) {
    const std::int64_t n = scene.color_count(v);
    std::copy(all.begin() + start[owner[v]], all.begin() + start[owner[v]] + n,
              global.begin() + scene.color_offset[v]);
    start[owner[v]] += n;
  }
  return global;
}

std::vector<Vec3f> localise_map(const BakeSceneHost& scene, const MapLayout& layout,
                                const std::vector<Vec3f>& global) {
  std::vector<Vec3f> local(static_cast<std::size_t>(layout.colors() + layout.halo_colors));
  for (std::int64_t v = 0; v < scene.vertices(); ++v) {
    for (std::int64_t j = 0; j < scene.color_count(v); ++j)
      if (layout.keeps(v, j)) local[layout.entry(v, j)] = global[scene.color_offset[v] + j];
  }
  return local;
}

void move_entry_records(const Communicator& comm, const BakeSceneHost& scene,
                        const std::vector<Batch>& from, const std::vector<Batch>& to,
                        RecordBytes mine, RecordBytes out, std::size_t record_bytes) {
  const int me = comm.rank(), ranks = comm.size();
  const auto& off = scene.color_offset;
  const std::int64_t rb = static_cast<std::int64_t>(record_bytes);
  // Where each range of `of` starts among `rank`'s records (the last entry: their count).
  auto first_record = [&](const std::vector<Batch>& of, int rank) {
    std::vector<std::int64_t> at(1, 0);
    for (const Batch& b : of)
      at.push_back(at.back() + (b.rank == rank ? off[b.end] - off[b.begin] : 0));
    return at;
  };
  const std::vector<std::int64_t> from_at = first_record(from, me), to_at = first_record(to, me);
  // n records from record `from_record` of `src` to record `to_record` of `dst` (one copy in
  // MemSpace, parallel on a host backend).
  const auto copy = [rb](RecordBytes dst, std::int64_t to_record, RecordBytes src,
                         std::int64_t from_record, std::int64_t n) {
    using Span = std::pair<std::int64_t, std::int64_t>;
    if (n == 0) return;
    Kokkos::deep_copy(Kokkos::subview(dst, Span(to_record * rb, (to_record + n) * rb)),
                      Kokkos::subview(src, Span(from_record * rb, (from_record + n) * rb)));
  };
  // Every overlap of a `from` range and a `to` range, in vertex order (both lists ascending): the
  // records a sender packs and a receiver unpacks for each pair of ranks, in the same order.
  struct Overlap {
    std::int64_t begin, end;
    int from_rank, to_rank;
    std::int64_t from_record, to_record;  // the overlap's first record on either side
  };
  std::vector<Overlap> overlaps;
  for (std::size_t i = 0, j = 0; i < from.size() && j < to.size();) {
    const std::int64_t b = std::max(from[i].begin, to[j].begin);
    const std::int64_t e = std::min(from[i].end, to[j].end);
    if (b < e)
      overlaps.push_back({b, e, from[i].rank, to[j].rank, from_at[i] + off[b] - off[from[i].begin],
                          to_at[j] + off[b] - off[to[j].begin]});
    if (from[i].end <= to[j].end)
      ++i;
    else
      ++j;
  }
  std::vector<int> send(ranks, 0), recv(ranks, 0);
  for (const Overlap& o : overlaps) {
    const std::int64_t n = off[o.end] - off[o.begin];
    if (o.from_rank == me && o.to_rank == me) {
      copy(out, o.to_record, mine, o.from_record, n);
    } else if (o.from_rank == me) {
      send[o.to_rank] += checked_int(n);
    } else if (o.to_rank == me) {
      recv[o.from_rank] += checked_int(n);
    }
  }
  // Packed by destination rank, each rank's overlaps in vertex order.
  std::vector<int> pos = displacements(send);
  const std::vector<int> recv_at = displacements(recv);
  const auto records = [](const std::vector<int>& at, const std::vector<int>& counts) {
    return static_cast<std::size_t>(at.back()) + static_cast<std::size_t>(counts.back());
  };
  using Buffer = Kokkos::View<unsigned char*, MemSpace>;
  Buffer packed(Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::moved_send"),
                records(pos, send) * record_bytes);
  Buffer received(Kokkos::view_alloc(Kokkos::WithoutInitializing, "rtmini::bake::moved_recv"),
                  records(recv_at, recv) * record_bytes);
  for (const Overlap& o : overlaps) {
    if (o.from_rank != me || o.to_rank == me) continue;
    const std::int64_t n = off[o.end] - off[o.begin];
    copy(RecordBytes(packed.data(), packed.extent(0)), pos[o.to_rank], mine, o.from_record, n);
    pos[o.to_rank] += static_cast<int>(n);
  }
  Kokkos::fence();  // the packed records must be in memory before MPI reads them
  if (mpi_takes_map_memory()) {
    alltoallv_records(comm, packed, send, received, recv, record_bytes);
  } else {
    std::vector<unsigned char> host_send(packed.extent(0)), host_recv(received.extent(0));
    Kokkos::deep_copy(compat::host_view(host_send.data(), host_send.size()), packed);
    alltoallv_records(comm, host_send, send, host_recv, recv, record_bytes);
    Kokkos::deep_copy(received, compat::host_view(host_recv.data(), host_recv.size()));
  }
  pos = recv_at;
  for (const Overlap& o : overlaps) {
    if (o.to_rank != me || o.from_rank == me) continue;
    const std::int64_t n = off[o.end] - off[o.begin];
    copy(out, o.to_record, RecordBytes(received.data(), received.extent(0)), pos[o.from_rank], n);
    pos[o.from_rank] += static_cast<int>(n);
  }
  Kokkos::fence();
}

}  // namespace rtmini::bake
