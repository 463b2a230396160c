#pragma once
// Compact binary Bake Shop map (.bsb): the same content as a .bs file (io/bakeshop.hpp),
// loaded by the web viewer (miniapps/bake/viewer) without text parsing.
//
// Byte layout, all little-endian. Every section starts at an 8-byte aligned offset
// (zero padding before it), so a reader can view it in place as a typed array.
//
//   offset  type      field
//   0       char[4]   magic "BSB1"
//   4       u32       flags: bit 0 kShared     one direction set shared by every vertex
//                            bit 1 kHalfColor  colours are IEEE float16, else float32
//                            bit 2 kPos64      positions are float64, else float32
//                            bit 3 kHemisphere a hemisphere map: the directions are in each
//                                              vertex's own frame (ViewpointColors::hemisphere)
//   8       u64       V  vertices
//   16      u64       M  materials
//   24      u64       F  faces
//   32      u64       O  objects
//   40      u64       D  direction vectors stored (N when kShared, else sum of counts)
//   48      u64       C  colour triples stored
//   56      u64       file size in bytes (detects truncation)
//   64      sections, in this order:
//     positions   V x 3 float32 (float64 with kPos64)
//     counts      V x u32   viewpoints of vertex i (0 = none)
//     uniform     V x u8    1: the vertex has one colour for all its viewpoints, stored once
//     dirs        D x 3 float32  camera-ray directions into the vertex; with kShared every
//                           vertex with a non-zero count has exactly these D directions
//     colours     C x 3 float32 (float16 with kHalfColor), linear RGB, vertex by vertex:
//                           1 triple for a uniform vertex, counts[i] triples otherwise
//     materials   M x 12 float32  diffuse rgb, reflective rgb, emissive rgb, Ns, Ni, d
//     faces       F x 6 i32  v0 v1 v2 v3 (v3 = -1: triangle), material (-1 = none), object
//     objects     O x (u32 length, bytes), object names
//
// The writer picks kShared when every vertex with viewpoints has bit-identical directions
// (the baker's Fibonacci set), marks a vertex uniform when its colours are bit-identical,
// and stores float32 positions only when that is lossless, so write -> read gives the
// identical Mesh (with float32 colours).
#include <cstdint>
#include <string>

#include "rtmini/scene/mesh.hpp"

namespace rtmini {

struct BakeshopBinaryOptions {
  // float16 colours halve the file; values are rounded (and clamped to +-65504).
  bool half_colors = false;
};

// Writes mesh atomically (temporary file + rename); IoError on failure.
void write_bakeshop_binary(const std::string& path, const Mesh& mesh,
                           const BakeshopBinaryOptions& options = {});

// The bytes of a .bsb file after its colour section: zero padding up to the next 8-byte file
// offset, then the materials, faces and objects sections. `colors_end` is the file offset where
// the colours end. One function for both writers: write_bakeshop_binary above and bake's
// parallel writer (miniapps/bake/bakeshop_mpi_writer.cpp: ranks write their own colours, rank 0
// this tail), so the two cannot drift apart.
std::string format_bakeshop_binary_tail(const Mesh& mesh, std::uint64_t colors_end);

// Reads a .bsb file; malformed input: InputError "file: reason (at byte B)".
Mesh read_bakeshop_binary(const std::string& path);

}  // namespace rtmini
