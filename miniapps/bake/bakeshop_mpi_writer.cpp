#include "bakeshop_mpi_writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/bakeshop_binary.hpp"
#include "rtmini/io/error.hpp"

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
  const auto& colors = *map.colors;
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
            out += format_bakeshop_vertex(p, dirs.data(), colors.data() + off[v], n);
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

bool is_binary_map_path(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".bsb";
}

namespace {

// The binary form (io/bakeshop_binary.hpp): every rank holds the whole map after the last
// all-gather, so rank 0 writes it alone; a view-independent vertex is expanded to N copies,
// which the writer stores once again (same Mesh as reading the text form back).
WriteStats write_baked_map_binary(const Communicator& comm, const std::string& path,
                                  const BakedMap& map) {
  const auto t0 = std::chrono::steady_clock::now();
  WriteStats stats;
  std::string error;
  if (comm.is_root()) {
    try {
      Mesh mesh = *map.mesh;
      const auto& off = *map.color_offset;
      const auto& colors = *map.colors;
      const auto& dirs = *map.directions;
      const std::size_t nv = mesh.positions.size(), n = dirs.size();
      ViewpointColors& vc = mesh.viewpoints;
      vc.offsets.resize(nv + 1);
      vc.dirs.reserve(nv * n);
      vc.colors.reserve(nv * n);
      for (std::size_t v = 0; v < nv; ++v) {
        vc.offsets[v] = vc.dirs.size();
        const bool uniform = off[v + 1] - off[v] == 1;
        for (std::size_t j = 0; j < n; ++j) {
          vc.dirs.push_back(dirs[j]);
          vc.colors.push_back(colors[static_cast<std::size_t>(off[v]) + (uniform ? 0 : j)]);
        }
      }
      vc.offsets[nv] = vc.dirs.size();
      write_bakeshop_binary(path, mesh);
      std::FILE* f = std::fopen(path.c_str(), "rb");
      if (f) {
        std::fseek(f, 0, SEEK_END);
        stats.file_bytes = std::ftell(f);
        std::fclose(f);
      }
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  stats.bytes_written = stats.file_bytes;
  // Every rank fails together when rank 0 could not write.
  if (comm.max(error.empty() ? 0.0 : 1.0) > 0.5)
    throw IoError(error.empty() ? path + ": binary map write failed on rank 0" : error);
  stats.file_bytes = static_cast<std::int64_t>(comm.max(static_cast<double>(stats.file_bytes)));
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace

WriteStats write_baked_map(const Communicator& comm, const std::string& path, const BakedMap& map,
                           const std::vector<VertexRange>& mine) {
  if (is_binary_map_path(path)) return write_baked_map_binary(comm, path, map);
  const auto t0 = std::chrono::steady_clock::now();
  WriteStats stats;
  std::vector<std::string> texts;
  texts.reserve(mine.size());
  for (const VertexRange& r : mine) texts.push_back(format_vertex_range(map, r));
  const std::string tail = comm.is_root() ? tail_text(*map.mesh) : std::string();

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
  std::int64_t offset = 0;
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
  MPI_File fh;
  int rc = MPI_File_open(comm.native(), tmp.c_str(), MPI_MODE_CREATE | MPI_MODE_WRONLY,
                         MPI_INFO_NULL, &fh);
  if (rc != MPI_SUCCESS) throw IoError(path + ": cannot create file (MPI_File_open failed)");
  rc = MPI_File_set_size(fh, 0);
  const int rounds = static_cast<int>(comm.max(static_cast<double>(pieces.size())));
  // Every rank takes part in every round even after an error (the writes are
  // collective: one rank leaving the loop early would hang the others); the
  // first error and any short count are remembered and agreed after close.
  bool counts_ok = true;
  for (int i = 0; i < rounds; ++i) {
    const bool have = i < static_cast<int>(pieces.size());
    const Piece p = have ? pieces[i] : Piece{0, nullptr, 0};
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
      commit_temporary(tmp, path, stats.file_bytes);
    } catch (const IoError& e) {
      problem = e.what();
    }
  }
  if (comm.max(problem.empty() ? 0.0 : 1.0) > 0.5)
    throw IoError(problem.empty() ? path + ": collective write failed on rank 0" : problem);
#else
  write_file_atomic(
      path,
      [&](const std::string& tmp) {
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) throw IoError(path + ": cannot create file: " + std::strerror(errno));
        bool wrote = true;
        for (const Piece& p : pieces)
          wrote = wrote && std::fwrite(p.data, 1, static_cast<std::size_t>(p.size), f) ==
                               static_cast<std::size_t>(p.size);
        const bool closed = std::fclose(f) == 0;
        if (!wrote || !closed) throw IoError(path + ": write failed: " + std::strerror(errno));
      },
      stats.file_bytes);
#endif
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace rtmini::bake
