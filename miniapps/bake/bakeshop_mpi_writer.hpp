#pragma once
// Writes the baked .bs map: every rank formats the vertex blocks it baked (io/bakeshop.hpp's
// format functions), the blocks are placed at the exclusive prefix sum of their byte sizes with
// collective MPI-IO (MPI_File_write_at_all), and rank 0 appends materials, faces and "!". No
// padding and no post-processing pass (the seed stripped null bytes afterwards). The file is
// written under a temporary name and renamed by rank 0 once every rank has closed it; without
// MPI it is one sequential atomic write. Same bytes for any rank count. A .bsb path gets the
// binary form instead (io/bakeshop_binary.hpp's bytes): every rank writes its vertices'
// colours, rank 0 the header, flags, directions, materials and faces.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/parallel/communicator.hpp"
#include "rtmini/scene/mesh.hpp"

namespace rtmini::bake {

struct VertexRange {
  std::int64_t begin = 0, end = 0;
};

// The baked map as the writer sees it (host data). colors holds, for each vertex v this rank
// writes, entries [color_offset[v], color_offset[v+1]): N view-dependent colours or 1
// view-independent one (expanded to N identical lines on output). A pointer, not a vector: on a
// host backend it is the bake's map itself, not a copy.
struct BakedMap {
  const Mesh* mesh = nullptr;
  const Vec3f* colors = nullptr;
  const std::vector<std::int64_t>* color_offset = nullptr;
  const std::vector<Vec3f>* directions = nullptr;  // the N viewpoint directions
  // The directions are the N/2 of a hemisphere map, in each vertex's frame (ViewpointColors):
  // the text form starts with kBakeshopHemisphereLine, the binary form sets its flag.
  bool hemisphere = false;
};

struct WriteStats {
  double seconds = 0;
  std::int64_t bytes_written = 0;  // by this rank
  std::int64_t file_bytes = 0;
};

// True for a path ending in .bsb (any case): the map is written in the binary form.
bool is_binary_map_path(const std::string& path);

// Collective over comm; the format follows the extension: .bsb binary, anything else text.
// `mine`: the vertex ranges this rank writes; the ranges of all ranks
// tile [0, vertices). IoError on failure.
WriteStats write_baked_map(const Communicator& comm, const std::string& path, const BakedMap& map,
                           const std::vector<VertexRange>& mine);

// The text of vertices [begin, end) (formatted in parallel on the host).
std::string format_vertex_range(const BakedMap& map, VertexRange range);

}  // namespace rtmini::bake
