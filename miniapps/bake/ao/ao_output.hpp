#pragma once
// Per-vertex AO output, chosen by the file extension; every writer is atomic
// (temp file + rename, io/atomic_file.hpp). Layouts are in README.md.
#include <string>
#include <vector>

#include "ao_scene.hpp"
#include "sample_plan.hpp"

namespace rtmini::ao {

enum class OutputFormat { kNone, kBin, kPly, kObj, kGlb };

// InputError "path: unsupported output extension" for anything but .bin .ply .obj .glb.
OutputFormat output_format(const std::string& path);

struct AoResult {
  const AoScene* scene = nullptr;
  const SamplePlan* plan = nullptr;
  std::vector<float> values;  // one per output vertex (plan.vertex_base order)
};

// The sample's raw layout: u64 instances, u64 vertices, {u64 mesh, u64 offset, u64 count}
// per receiver instance, then one f32 per vertex; all little endian.
void write_ao_bin(const std::string& path, const AoResult& result);
// World-space receivers flattened: x y z (f32), red green blue (u8 = 255 * clamp(ao)), ao (f32).
void write_ao_ply(const std::string& path, const AoResult& result, bool ascii);
// World-space receivers flattened, `v x y z r g b` with r = g = b = clamp(ao), `f` 1-based.
void write_ao_obj(const std::string& path, const AoResult& result);
// glTF 2.0 binary: one POSITION + indices per stored mesh, one node per receiver
// instance (its matrix) with its own COLOR_0 (float RGB = clamp(ao), linear).
void write_ao_glb(const std::string& path, const AoResult& result);

void write_ao_output(const std::string& path, const AoResult& result, bool ply_ascii);

}  // namespace rtmini::ao
