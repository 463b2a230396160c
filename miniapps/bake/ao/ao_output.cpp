#include "ao_output.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/io/raw_bytes.hpp"

namespace rtmini::ao {
namespace {

std::ofstream open_binary(const std::string& tmp) {
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError("cannot open " + tmp + " for writing");
  return out;
}

void finish(std::ofstream& out, const std::string& tmp) {
  out.flush();
  if (!out) throw IoError("write failed: " + tmp);
}

float clamp01(float v) { return v < 0.f ? 0.f : (v > 1.f ? 1.f : v); }

// Calls fn(world position, value) per output vertex and tri(a, b, c) per triangle (global ids).
template <class VertexFn, class TriFn>
void for_each_flat(const AoResult& res, VertexFn&& vfn, TriFn&& tfn) {
  const SamplePlan& plan = *res.plan;
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoInstance& inst = res.scene->instances[plan.receivers[r]];
    const AoMesh& mesh = res.scene->meshes[inst.mesh];
    const std::int64_t base = plan.vertex_base[r];
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      vfn(inst.xform.point(mesh.positions[v]), res.values[base + static_cast<std::int64_t>(v)]);
  }
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    const AoMesh& mesh = res.scene->meshes[res.scene->instances[plan.receivers[r]].mesh];
    const std::int64_t base = plan.vertex_base[r];
    for (const auto& t : mesh.tris) tfn(base + t[0], base + t[1], base + t[2]);
  }
}

}  // namespace

OutputFormat output_format(const std::string& path) {
  if (path.empty()) return OutputFormat::kNone;
  const std::string ext = lower_extension(path);
  if (ext == ".bin") return OutputFormat::kBin;
  if (ext == ".ply") return OutputFormat::kPly;
  if (ext == ".obj") return OutputFormat::kObj;
  if (ext == ".glb") return OutputFormat::kGlb;
  throw InputError(path, 0,
                   "unsupported output extension '" + ext + "' (use .bin, .ply, .obj or .glb)");
}

void write_ao_bin(const std::string& path, const AoResult& res) {
  const SamplePlan& plan = *res.plan;
  std::string buf;
  append_raw(buf, static_cast<std::uint64_t>(plan.receivers.size()));
  append_raw(buf, static_cast<std::uint64_t>(plan.total_vertices()));
  for (std::size_t r = 0; r < plan.receivers.size(); ++r) {
    append_raw(buf, static_cast<std::uint64_t>(res.scene->instances[plan.receivers[r]].mesh));
    append_raw(buf, static_cast<std::uint64_t>(plan.vertex_base[r]));
    append_raw(buf, static_cast<std::uint64_t>(plan.vertex_base[r + 1] - plan.vertex_base[r]));
  }
  buf.append(reinterpret_cast<const char*>(res.values.data()), res.values.size() * sizeof(float));
  write_text_atomic(path, buf);
}

void write_ao_ply(const std::string& path, const AoResult& res, bool ascii) {
  write_file_atomic(path, [&](const std::string& tmp) {
    std::ofstream out = open_binary(tmp);
    const std::int64_t nv = res.plan->total_vertices(), nt = res.plan->total_triangles();
    out << "ply\nformat " << (ascii ? "ascii" : "binary_little_endian") << " 1.0\n"
        << "comment rtmini bake --mode ao: per-vertex ambient occlusion (1 = open)\n"
        << "element vertex " << nv << "\nproperty float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float ao\n"
        << "element face " << nt << "\nproperty list uchar int vertex_indices\nend_header\n";
    std::string buf;
    char line[160];
    for_each_flat(
        res,
        [&](const Vec3d& p, float ao) {
          const auto c = static_cast<unsigned char>(std::lround(255.0f * clamp01(ao)));
          if (ascii) {
            std::snprintf(line, sizeof line, "%.9g %.9g %.9g %u %u %u %.9g\n",
                          static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z),
                          c, c, c, ao);
            buf += line;
          } else {
            append_raw(buf, static_cast<float>(p.x));
            append_raw(buf, static_cast<float>(p.y));
            append_raw(buf, static_cast<float>(p.z));
            append_raw(buf, c);
            append_raw(buf, c);
            append_raw(buf, c);
            append_raw(buf, ao);
          }
        },
        [&](std::int64_t a, std::int64_t b, std::int64_t c) {
          if (ascii) {
            std::snprintf(line, sizeof line, "3 %lld %lld %lld\n", static_cast<long long>(a),
                          static_cast<long long>(b), static_cast<long long>(c));
            buf += line;
          } else {
            append_raw(buf, static_cast<unsigned char>(3));
            append_raw(buf, static_cast<std::int32_t>(a));
            append_raw(buf, static_cast<std::int32_t>(b));
            append_raw(buf, static_cast<std::int32_t>(c));
          }
        });
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    finish(out, tmp);
  });
}

void write_ao_obj(const std::string& path, const AoResult& res) {
  write_file_atomic(path, [&](const std::string& tmp) {
    std::ofstream out = open_binary(tmp);
    std::string buf =
        "# rtmini bake --mode ao: per-vertex ambient occlusion as vertex colour (1 = open)\n";
    char line[160];
    for_each_flat(
        res,
        [&](const Vec3d& p, float ao) {
          const float c = clamp01(ao);
          std::snprintf(line, sizeof line, "v %.9g %.9g %.9g %.6g %.6g %.6g\n",
                        static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z),
                        c, c, c);
          buf += line;
        },
        [&](std::int64_t a, std::int64_t b, std::int64_t c) {
          std::snprintf(line, sizeof line, "f %lld %lld %lld\n", static_cast<long long>(a + 1),
                        static_cast<long long>(b + 1), static_cast<long long>(c + 1));
          buf += line;
        });
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    finish(out, tmp);
  });
}

void write_ao_output(const std::string& path, const AoResult& result, bool ply_ascii) {
  switch (output_format(path)) {
    case OutputFormat::kBin:
      write_ao_bin(path, result);
      break;
    case OutputFormat::kPly:
      write_ao_ply(path, result, ply_ascii);
      break;
    case OutputFormat::kObj:
      write_ao_obj(path, result);
      break;
    case OutputFormat::kGlb:
      write_ao_glb(path, result);
      break;
    case OutputFormat::kNone:
      break;
  }
}

}  // namespace rtmini::ao
