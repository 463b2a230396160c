#include "bakeshop_mpi_writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/bakeshop_binary.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/path.hpp"

namespace rtmini::bake {
namespace {

constexpr std::int64_t kVerticesPerTask = 256;
constexpr std::int64_t kMaxPiece = std::int64_t(1) << 30;  // MPI counts are int

std::string tail_text(const Mesh& mesh) {
  return "\n" + format_bakeshop_materials(mesh) + "\n" + format_bakeshop_faces(mesh) + "!\n";
}

struct Piece {
  std::int64_t offset;
  const char* data;
  std::int64_t size;
};

}  // namespace

std::string format_vertex_range(const BakedMap& map, VertexRange range) {
  const auto& off = *map.color_offset;
  const Vec3f* colors = map.colors;
  const auto& dirs = *map.directions;
  const std::size_t n = dirs.size();
  const std::int64_t count = range.end - range.begin;
  const std::int64_t tasks = (count + kVerticesPerTask - 1) / kVerticesPerTask;
  std::vector<std::string> parts(static_cast<std::size_t>(tasks));
  Kokkos::parallel_for(
      "rtmini::bake::format_vertices",
      Kokkos::RangePolicy<Kokkos::DefaultHostExecutionSpace, Kokkos::Schedule<Kokkos::Dynamic>>(
          0, tasks),
      [&](std::int64_t t) {
        std::string& out = parts[t];
        const std::int64_t b = range.begin + t * kVerticesPerTask;
        const std::int64_t e = std::min(range.end, b + kVerticesPerTask);
        for (std::int64_t v = b; v < e; ++v) {
          const Vec3d& p = map.mesh->positions[v];
          if (off[v + 1] - off[v] == 1)
            out += format_bakeshop_vertex_uniform(p, dirs.data(), n, colors[off[v]]);
          else
            out += format_bakeshop_vertex(p, dirs.data(), colors + off[v], n);
        }
      });
  std::size_t total = 0;
  for (const auto& s : parts) total += s.size();
  std::string out;
  out.reserve(total);
  for (auto& s : parts) {
    out += s;
    std::string().swap(s);
  }
  return out;
}

bool is_binary_map_path(const std::string& path) { return lower_extension(path) == ".bsb"; }

namespace {

// Little-endian bytes of plain values (the layout of io/bakeshop_binary.hpp; x86 and ARM). The
// head starts at file offset 0, so buffer and file alignment agree.
struct Bytes {
  std::string out;
  template <class T>
  void put(T value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof(T));
  }
  void align8() { out.resize((out.size() + 7) / 8 * 8, '\0'); }
};

std::int64_t align8(std::int64_t n) { return (n + 7) / 8 * 8; }

bool float_exact(double v) { return static_cast<double>(static_cast<float>(v)) == v; }

bool positions_fit_float(const Mesh& mesh) {
  for (const Vec3d& p : mesh.positions)
    if (!float_exact(p.x) || !float_exact(p.y) || !float_exact(p.z)) return false;
  return true;
}

// Bytes before the colour section: header, positions, counts, uniform flags, directions.
std::int64_t binary_head_bytes(std::int64_t nv, std::int64_t n, bool pos32) {
  std::int64_t at = 64 + align8(nv * 3 * (pos32 ? 4 : 8));
  at += align8(nv * 4) + align8(nv);
  return at + align8(n * 3 * 4);
}

// Whether vertex v's colours are all the same bits (the binary form then stores one).
bool uniform_colors(const BakedMap& map, std::int64_t v) {
  const auto& off = *map.color_offset;
  const Vec3f* c = map.colors + off[v];
  for (std::int64_t k = 1; k < off[v + 1] - off[v]; ++k)
    if (std::memcmp(&c[k], &c[0], sizeof(Vec3f)) != 0) return false;
  return true;
}

// This rank's vertices in binary form: uniform flags, and the colours each range stores.
struct BinaryPart {
  std::vector<std::uint8_t> uniform;
  std::vector<std::int64_t> stored;  // colours stored per range
};

BinaryPart binary_part(const BakedMap& map, const std::vector<VertexRange>& mine) {
  const std::int64_t n = static_cast<std::int64_t>(map.directions->size());
  BinaryPart part;
  for (const VertexRange& r : mine) {
    std::int64_t stored = 0;
    for (std::int64_t v = r.begin; v < r.end; ++v) {
      const bool same = uniform_colors(map, v);
      part.uniform.push_back(same ? 1 : 0);
      stored += same ? 1 : n;
    }
    part.stored.push_back(stored);
  }
  return part;
}

// A piece of this rank's colour section: vertices [begin, end) of one range, at `offset` in the
// file, `bytes` long (packed into a bounded buffer just before it is written).
struct ColorChunk {
  std::int64_t begin, end, offset, bytes;
};

// The binary colour section is written in chunks packed from the map as they go: packed whole, it
// was a second copy of the rank's colours at the run's peak (a quarter of the 1-rank bake's
// resident memory on bunny_room). A chunk is an eighth of the rank's own colour bytes, between
// 1 and 16 MiB, so it stays small beside the colours at any rank count; at 16 ranks of
// bunny_room (0.5 GiB of colours) a 16 MiB chunk held all of a rank's colours at once. The
// environment's RTMINI_BSB_CHUNK_BYTES sets the chunk instead: the ctest bake.binary_output
// writes with tiny chunks and compares the bytes.
std::int64_t chunk_bytes(std::int64_t own_bytes) {
  const char* e = std::getenv("RTMINI_BSB_CHUNK_BYTES");
  const std::int64_t n = e ? std::atoll(e) : 0;
  if (n > 0) return n;
  constexpr std::int64_t kMiB = std::int64_t(1) << 20;
  return std::clamp(own_bytes / 8, kMiB, 16 * kMiB);
}

std::vector<ColorChunk> color_chunks(const BakedMap& map, const std::vector<VertexRange>& mine,
                                     const std::vector<std::int64_t>& range_offset,
                                     const std::vector<std::uint8_t>& uniform) {
  const std::int64_t n = static_cast<std::int64_t>(map.directions->size());
  std::int64_t own_bytes = 0;
  for (std::size_t f = 0; f < uniform.size(); ++f) own_bytes += (uniform[f] ? 1 : n) * 12;
  const std::int64_t most = chunk_bytes(own_bytes);
  std::vector<ColorChunk> chunks;
  std::size_t flag = 0;
  for (std::size_t i = 0; i < mine.size(); ++i) {
    ColorChunk c{mine[i].begin, mine[i].begin, range_offset[i], 0};
    for (std::int64_t v = mine[i].begin; v < mine[i].end; ++v) {
      const std::int64_t bytes = (uniform[flag++] ? 1 : n) * 12;
      if (c.bytes > 0 && c.bytes + bytes > most) {
        chunks.push_back(c);
        c = {v, v, c.offset + c.bytes, 0};
      }
      c.end = v + 1;
      c.bytes += bytes;
    }
    if (c.bytes > 0) chunks.push_back(c);
  }
  return chunks;
}

// The stored colours of a chunk's vertices into `out` (one for a uniform vertex, else all N).
void pack_chunk(const BakedMap& map, const ColorChunk& c, std::string& out) {
  const auto& off = *map.color_offset;
  out.clear();
  for (std::int64_t v = c.begin; v < c.end; ++v) {
    const std::int64_t count = uniform_colors(map, v) ? 1 : off[v + 1] - off[v];
    out.append(reinterpret_cast<const char*>(map.colors + off[v]),
               static_cast<std::size_t>(count) * sizeof(Vec3f));
  }
}

// Header (with the colour count and file size), positions, counts, flags and directions.
std::string binary_head(const BakedMap& map, const std::vector<std::uint8_t>& uniform,
                        std::int64_t colors, std::int64_t file_size, bool pos32) {
  const Mesh& mesh = *map.mesh;
  const std::size_t nv = mesh.positions.size(), n = map.directions->size();
  Bytes w;
  w.out.append("BSB1", 4);
  // shared directions; float64 positions; hemisphere (io/bakeshop_binary.hpp)
  w.put<std::uint32_t>(1u | (pos32 ? 0u : 4u) | (map.hemisphere ? 8u : 0u));
  for (std::uint64_t x : {std::uint64_t(nv), std::uint64_t(mesh.materials.size()),
                          std::uint64_t(mesh.faces.size()), std::uint64_t(mesh.objects.size()),
                          std::uint64_t(n), std::uint64_t(colors), std::uint64_t(file_size)})
    w.put(x);
  for (const Vec3d& p : mesh.positions) {
    if (pos32)
      for (double x : {p.x, p.y, p.z}) w.put(static_cast<float>(x));
    else
      for (double x : {p.x, p.y, p.z}) w.put(x);
  }
  w.align8();
  for (std::size_t i = 0; i < nv; ++i) w.put(static_cast<std::uint32_t>(n));
  w.align8();
  w.out.append(reinterpret_cast<const char*>(uniform.data()), uniform.size());
  w.align8();
  for (const Vec3f& d : *map.directions)
    for (float x : {d.x, d.y, d.z}) w.put(x);
  w.align8();
  return w.out;
}

}  // namespace

namespace {

// Piece i of a rank's pieces; its data need stay valid only until the next call.
using PieceSource = std::function<Piece(std::size_t)>;

// Writes every rank's `count` pieces at their offsets into `path` (collective MPI-IO under a
// temporary name, renamed by rank 0 once all have closed it; without MPI one sequential atomic
// write). collective_buffer_bytes > 0 (the same on every rank) bounds the buffer of each rank
// that aggregates the collective writes (the "cb_buffer_size" hint): Open MPI's OMPIO takes
// 32 MiB by default (io_ompio_bytes_per_agg), which at 16 ranks of bunny_room was more than a
// rank's own colours and set the run's peak.
void write_pieces(const Communicator& comm, const std::string& path, std::size_t count,
                  const PieceSource& piece, std::int64_t file_bytes,
                  std::int64_t collective_buffer_bytes = 0) {
#ifdef RTMINI_HAVE_MPI
  // Rank 0 checks the target (regular file or absent) and clears dead runs'
  // temporaries; the pid broadcast is the agreement before the collective open.
  if (comm.is_root()) {
    check_replaceable(path);
    remove_stale_temporaries(path);
  }
  std::vector<std::int64_t> pid{comm.is_root() ? static_cast<std::int64_t>(::getpid()) : 0};
  comm.broadcast(pid);
  const std::string tmp = path + ".tmp." + std::to_string(pid[0]);
  MPI_Info info = MPI_INFO_NULL;
  if (collective_buffer_bytes > 0) {
    MPI_Info_create(&info);
    MPI_Info_set(info, "cb_buffer_size", std::to_string(collective_buffer_bytes).c_str());
  }
  MPI_File fh;
  int rc = MPI_File_open(comm.native(), tmp.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY, info, &fh);
  if (info != MPI_INFO_NULL) MPI_Info_free(&info);
  if (rc != MPI_SUCCESS) throw IoError(path + ": cannot create file (MPI_File_open failed)");
  rc = MPI_File_set_size(fh, 0);
  const int rounds = static_cast<int>(comm.max(static_cast<double>(count)));
  // Every rank takes part in every round even after an error (the writes are
  // collective: one rank leaving the loop early would hang the others); the
  // first error and any short count are remembered and agreed after close.
  bool counts_ok = true;
  for (int i = 0; i < rounds; ++i) {
    const bool have = i < static_cast<int>(count);
    const Piece p = have ? piece(static_cast<std::size_t>(i)) : Piece{0, nullptr, 0};
    MPI_Status status;
    const int wrc = MPI_File_write_at_all(fh, static_cast<MPI_Offset>(p.offset), p.data,
                                          static_cast<int>(p.size), MPI_BYTE, &status);
    int written = 0;
    if (wrc == MPI_SUCCESS) MPI_Get_count(&status, MPI_BYTE, &written);
    counts_ok = counts_ok && written == static_cast<int>(p.size);
    if (rc == MPI_SUCCESS) rc = wrc;
  }
  const int close_rc = MPI_File_close(&fh);
  const bool ok =
      comm.min(rc == MPI_SUCCESS && counts_ok && close_rc == MPI_SUCCESS ? 1.0 : 0.0) > 0.5;
  if (!ok) {
    if (comm.is_root()) std::remove(tmp.c_str());
    throw IoError(path + ": collective write failed (an MPI-IO error or a short write)");
  }
  // Open MPI's default component (OMPIO) does not report a full disk from the
  // writes: the size of the closed file is the check, on rank 0, then agreed.
  std::string problem;
  if (comm.is_root()) {
    try {
      commit_temporary(tmp, path, file_bytes);
    } catch (const IoError& e) {
      problem = e.what();
    }
  }
  if (comm.max(problem.empty() ? 0.0 : 1.0) > 0.5)
    throw IoError(problem.empty() ? path + ": collective write failed on rank 0" : problem);
#else
  (void)collective_buffer_bytes;  // one process writes alone
  write_file_atomic(
      path,
      [&](const std::string& tmp) {
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) throw IoError(path + ": cannot create file: " + std::strerror(errno));
        bool wrote = true;
        for (std::size_t i = 0; i < count; ++i) {
          const Piece p = piece(i);
          wrote = wrote && std::fseek(f, static_cast<long>(p.offset), SEEK_SET) == 0 &&
                  std::fwrite(p.data, 1, static_cast<std::size_t>(p.size), f) ==
                      static_cast<std::size_t>(p.size);
        }
        const bool closed = std::fclose(f) == 0;
        if (!wrote || !closed) throw IoError(path + ": write failed: " + std::strerror(errno));
      },
      file_bytes);
#endif
}

// Splits [data, data + size) at `offset` into pieces MPI's int counts can take.
void add_pieces(std::vector<Piece>& pieces, std::int64_t offset, const char* data,
                std::int64_t size) {
  for (std::int64_t o = 0; o < size; o += kMaxPiece)
    pieces.push_back({offset + o, data + o, std::min(kMaxPiece, size - o)});
}

// The binary form: every rank writes the colours of its own vertices at the prefix sum of the
// colours stored before them; rank 0 writes the header, positions, flags and directions (the
// flags gathered, one byte per vertex) and the materials and faces after the colours. The same
// bytes as io/bakeshop_binary.hpp's writer, without the whole map on any rank.
WriteStats write_baked_map_binary(const Communicator& comm, const std::string& path,
                                  const BakedMap& map, const std::vector<VertexRange>& mine) {
  const auto t0 = std::chrono::steady_clock::now();
  const Mesh& mesh = *map.mesh;
  const BinaryPart part = binary_part(map, mine);
  std::vector<std::int64_t> my_ranges;  // (begin, end, stored) triples
  for (std::size_t i = 0; i < mine.size(); ++i)
    my_ranges.insert(my_ranges.end(), {mine[i].begin, mine[i].end, part.stored[i]});
  const std::vector<std::int64_t> all = comm.allgatherv(my_ranges);
  const std::vector<std::uint8_t> flags = comm.gatherv(part.uniform);
  std::vector<std::array<std::int64_t, 3>> ranges;
  for (std::size_t i = 0; i + 2 < all.size(); i += 3)
    ranges.push_back({all[i], all[i + 1], all[i + 2]});
  const bool pos32 = positions_fit_float(mesh);
  const std::int64_t nv = static_cast<std::int64_t>(mesh.positions.size());
  const std::int64_t start =
      binary_head_bytes(nv, static_cast<std::int64_t>(map.directions->size()), pos32);
  std::vector<std::uint8_t> uniform(comm.is_root() ? static_cast<std::size_t>(nv) : 0);
  std::size_t next_flag = 0;
  for (const auto& r : ranges)  // gathered in the order of `all`
    for (std::int64_t v = r[0]; v < r[1] && comm.is_root(); ++v) uniform[v] = flags[next_flag++];
  std::sort(ranges.begin(), ranges.end());
  // Where each of this rank's ranges starts in the file (ranges tile the vertices in order).
  std::vector<std::int64_t> range_offset(mine.size());
  std::int64_t at = start;
  for (const auto& r : ranges) {
    for (std::size_t i = 0; i < mine.size(); ++i)
      if (mine[i].begin == r[0]) range_offset[i] = at;
    at += r[2] * 12;
  }
  std::string head, tail;
  std::vector<Piece> fixed;  // the root's header and tail
  if (comm.is_root()) {
    tail = format_bakeshop_binary_tail(mesh, static_cast<std::uint64_t>(at));
    head = binary_head(map, uniform, (at - start) / 12, at + static_cast<std::int64_t>(tail.size()),
                       pos32);
    add_pieces(fixed, 0, head.data(), static_cast<std::int64_t>(head.size()));
    add_pieces(fixed, at, tail.data(), static_cast<std::int64_t>(tail.size()));
  }
  const std::vector<ColorChunk> chunks = color_chunks(map, mine, range_offset, part.uniform);
  WriteStats stats;
  for (const Piece& p : fixed) stats.bytes_written += p.size;
  for (const ColorChunk& c : chunks) stats.bytes_written += c.bytes;
  stats.file_bytes = at + static_cast<std::int64_t>(comm.max(double(tail.size())));
  // The aggregators' buffers no larger than the largest rank's chunk.
  std::int64_t largest_chunk = 0;
  for (const ColorChunk& c : chunks) largest_chunk = std::max(largest_chunk, c.bytes);
  largest_chunk = static_cast<std::int64_t>(comm.max(static_cast<double>(largest_chunk)));
  std::string buffer;
  write_pieces(
      comm, path, fixed.size() + chunks.size(),
      [&](std::size_t i) {
        if (i < fixed.size()) return fixed[i];
        const ColorChunk& c = chunks[i - fixed.size()];
        pack_chunk(map, c, buffer);
        return Piece{c.offset, buffer.data(), static_cast<std::int64_t>(buffer.size())};
      },
      stats.file_bytes, largest_chunk);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace

WriteStats write_baked_map(const Communicator& comm, const std::string& path, const BakedMap& map,
                           const std::vector<VertexRange>& mine) {
  if (is_binary_map_path(path)) return write_baked_map_binary(comm, path, map, mine);
  const auto t0 = std::chrono::steady_clock::now();
  WriteStats stats;
  std::vector<std::string> texts;
  texts.reserve(mine.size());
  for (const VertexRange& r : mine) texts.push_back(format_vertex_range(map, r));
  const std::string tail = comm.is_root() ? tail_text(*map.mesh) : std::string();
  const std::string head = map.hemisphere ? kBakeshopHemisphereLine : "";

  // Exclusive prefix sum of the block sizes, in vertex order, over every rank's blocks.
  std::vector<std::int64_t> my_blocks;  // (begin, size) pairs
  for (std::size_t i = 0; i < mine.size(); ++i) {
    my_blocks.push_back(mine[i].begin);
    my_blocks.push_back(static_cast<std::int64_t>(texts[i].size()));
  }
  std::vector<std::int64_t> all = comm.allgatherv(my_blocks);
  std::vector<std::pair<std::int64_t, std::int64_t>> blocks;
  for (std::size_t i = 0; i + 1 < all.size(); i += 2) blocks.emplace_back(all[i], all[i + 1]);
  std::sort(blocks.begin(), blocks.end());
  std::vector<Piece> pieces;
  std::int64_t offset = static_cast<std::int64_t>(head.size());
  if (comm.is_root() && !head.empty())
    pieces.push_back({0, head.data(), static_cast<std::int64_t>(head.size())});
  for (const auto& b : blocks) {
    for (std::size_t i = 0; i < mine.size(); ++i) {
      if (mine[i].begin != b.first) continue;
      for (std::int64_t o = 0; o < b.second; o += kMaxPiece)
        pieces.push_back({offset + o, texts[i].data() + o, std::min(kMaxPiece, b.second - o)});
    }
    offset += b.second;
  }
  if (comm.is_root() && !tail.empty())
    pieces.push_back({offset, tail.data(), static_cast<std::int64_t>(tail.size())});
  stats.file_bytes = offset + static_cast<std::int64_t>(comm.max(double(tail.size())));
  for (const Piece& p : pieces) stats.bytes_written += p.size;

  write_pieces(
      comm, path, pieces.size(), [&](std::size_t i) { return pieces[i]; }, stats.file_bytes);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace rtmini::bake
