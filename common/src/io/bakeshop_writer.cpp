#include <charconv>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/bakeshop.hpp"

namespace rtmini {
namespace {

// Shortest round-trip form (std::to_chars): the text reads back to the same bits, and the same
// value gives the same bytes on every rank and thread, whatever the locale (printf's %g is
// neither exact nor locale-proof). The .bs hashes of the regression tests rely on it.
template <class T>
void append_number(std::string& out, T value) {
  char buf[32];
  const auto result = std::to_chars(buf, buf + sizeof(buf), value);
  out.append(buf, result.ptr);
}

template <class T>
void append_vec(std::string& out, const Vec3T<T>& v) {
  append_number(out, v.x);
  out += ' ';
  append_number(out, v.y);
  out += ' ';
  append_number(out, v.z);
}

void append_viewpoint(std::string& out, const Vec3f& dir, const Vec3f& color) {
  out += "| ";
  append_vec(out, dir);
  out += ' ';
  append_vec(out, color);
  out += '\n';
}

}  // namespace

std::string format_bakeshop_vertex(const Vec3d& p, const Vec3f* dirs, const Vec3f* colors,
                                   std::size_t n) {
  std::string out;
  append_vec(out, p);
  out += '\n';
  for (std::size_t i = 0; i < n; ++i) append_viewpoint(out, dirs[i], colors[i]);
  return out;
}

std::string format_bakeshop_vertex_uniform(const Vec3d& p, const Vec3f* dirs, std::size_t n,
                                           const Vec3f& color) {
  std::string out;
  append_vec(out, p);
  out += '\n';
  for (std::size_t i = 0; i < n; ++i) append_viewpoint(out, dirs[i], color);
  return out;
}

std::string format_bakeshop_materials(const Mesh& mesh) {
  std::string out;
  for (const Material& m : mesh.materials) {
    out += ": ";
    append_vec(out, m.diffuse);
    out += "  ";
    append_vec(out, m.reflective);
    out += "  ";
    append_vec(out, m.emissive);
    out += '\n';
  }
  return out;
}

std::string format_bakeshop_faces(const Mesh& mesh) {
  std::string out;
  for (const Face& f : mesh.faces) {
    for (int k = 0; k < f.count; ++k) {
      append_number(out, f.v[k]);
      out += ' ';
    }
    append_number(out, f.material);
    out += '\n';
  }
  return out;
}

// Vertex blocks, a blank line, materials, a blank line, faces, and "!" closing the file: the
// reader (bakeshop_reader.cpp) needs the blank lines to tell the sections apart.
std::string format_bakeshop(const Mesh& mesh) {
  std::string out;
  const ViewpointColors& vp = mesh.viewpoints;
  const bool has_views = !vp.offsets.empty();
  if (has_views && vp.hemisphere) out += kBakeshopHemisphereLine;
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    if (has_views) {
      const std::size_t b = vp.offsets[i];
      out += format_bakeshop_vertex(mesh.positions[i], vp.dirs.data() + b, vp.colors.data() + b,
                                    vp.offsets[i + 1] - b);
    } else {
      out += format_bakeshop_vertex(mesh.positions[i], nullptr, nullptr, 0);
    }
  }
  out += '\n';
  out += format_bakeshop_materials(mesh);
  out += '\n';
  out += format_bakeshop_faces(mesh);
  out += "!\n";
  return out;
}

void write_bakeshop(const std::string& path, const Mesh& mesh) {
  write_text_atomic(path, format_bakeshop(mesh));
}

}  // namespace rtmini
