#include <cmath>
#include <type_traits>

#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/text_fields.hpp"

namespace rtmini {
namespace {

// The format has no section keywords: one blank line moves to the next section, '!' ends the
// file. Hence the order of the enumerators matters (a blank line adds one).
enum class Section { kVertices = 0, kMaterials = 1, kFaces = 2, kDone = 3 };

std::string_view trim_left(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return s;
}

std::string file_stem(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

class BakeshopParser {
 public:
  explicit BakeshopParser(const std::string& path) : path_(path) {}

  Mesh parse(std::string_view text) {
    // .bs has no object names: the whole file is one object named after it (the stem shows up
    // in summaries and in the viewer's object list).
    mesh_.objects.push_back(file_stem(path_));
    mesh_.viewpoints.offsets.push_back(0);
    detail::LineCursor cursor(text);
    std::string_view line;
    while (cursor.next(line)) {
      line_ = cursor.line_number();
      parse_line(trim_left(line));
    }
    if (line_ == 0) fail(1, "empty file (expected vertices, materials, faces and a final '!')");
    if (section_ != Section::kDone) fail(line_, "missing '!' at end of file");
    // A plain scene (no '|' lines) has no viewpoint table at all: empty offsets is how a Mesh
    // says "not a baked map", and writers and the renderer test for that.
    if (mesh_.viewpoints.dirs.empty()) {
      if (mesh_.viewpoints.hemisphere) fail(1, "'# hemisphere' header but no viewpoint lines");
      mesh_.viewpoints.offsets.clear();
    }
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(long line, const std::string& reason) const {
    throw InputError(path_, line, reason);
  }

  void parse_line(std::string_view line) {
    if (line_ == 1 && line.substr(0, 1) == "#") {
      if (detail::split_fields(line) != std::vector<std::string_view>{"#", "hemisphere"})
        fail(line_, "unknown header line (the only one is '# hemisphere')");
      mesh_.viewpoints.hemisphere = true;
      return;
    }
    const bool blank = detail::split_fields(line).empty();
    if (section_ == Section::kDone) {
      if (!blank) fail(line_, "unexpected content after the final '!'");
      return;
    }
    if (blank) {
      if (section_ == Section::kFaces) fail(line_, "blank line inside the faces section");
      section_ = static_cast<Section>(static_cast<int>(section_) + 1);
      return;
    }
    if (line.front() == '!') {
      if (!detail::split_fields(line.substr(1)).empty())
        fail(line_, "unexpected content after '!'");
      if (section_ != Section::kFaces)
        fail(line_, "'!' before the faces section (sections are separated by one blank line)");
      section_ = Section::kDone;
      return;
    }
    switch (section_) {
      case Section::kVertices:
        if (line.front() == '|') {
          parse_viewpoint(line.substr(1));
        } else if (line.front() == ':') {
          fail(line_, "material line in the vertices section (missing blank line?)");
        } else {
          parse_vertex(line);
        }
        break;
      case Section::kMaterials:
        if (line.front() != ':')
          fail(line_, "expected a material line ': dr dg db  sr sg sb  er eg eb'");
        parse_material(line.substr(1));
        break;
      default:
        parse_face(line);
        break;
    }
  }

  // Every number is checked where it is read: non-finite values, and values that would overflow
  // Real (float unless RTMINI_DOUBLE) once uploaded, are input errors with their line, not NaNs
  // found later in a kernel.
  template <class T>
  T number(std::string_view field, const char* what) const {
    const auto value = detail::parse_number<T>(field);
    if (!value) fail(line_, std::string("invalid number '") + std::string(field) + "' in " + what);
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(*value))
        fail(line_, std::string("non-finite value '") + std::string(field) + "' in " + what);
      if (!detail::fits_real(static_cast<double>(*value)))
        fail(line_, std::string("value '") + std::string(field) + "' in " + what +
                        " is beyond the " + detail::real_range_name() +
                        " range (non-finite once uploaded)");
    }
    return *value;
  }

  template <class T>
  Vec3T<T> vec(const std::vector<std::string_view>& f, std::size_t first, const char* what) const {
    return {number<T>(f[first], what), number<T>(f[first + 1], what),
            number<T>(f[first + 2], what)};
  }

  void expect_fields(const std::vector<std::string_view>& f, std::size_t n,
                     const char* what) const {
    if (f.size() != n)
      fail(line_, std::string(what) + " needs " + std::to_string(n) + " fields, got " +
                      std::to_string(f.size()));
  }

  void parse_vertex(std::string_view line) {
    const auto f = detail::split_fields(line);
    expect_fields(f, 3, "vertex");
    mesh_.positions.push_back(vec<double>(f, 0, "vertex"));
    mesh_.viewpoints.offsets.push_back(mesh_.viewpoints.dirs.size());
  }

  // A viewpoint belongs to the vertex above it: offsets.back() is that vertex's end.
  void parse_viewpoint(std::string_view rest) {
    if (mesh_.positions.empty()) fail(line_, "viewpoint line before any vertex");
    const auto f = detail::split_fields(rest);
    expect_fields(f, 6, "viewpoint '| dx dy dz r g b'");
    mesh_.viewpoints.dirs.push_back(vec<float>(f, 0, "viewpoint"));
    mesh_.viewpoints.colors.push_back(vec<float>(f, 3, "viewpoint"));
    mesh_.viewpoints.offsets.back() = mesh_.viewpoints.dirs.size();
  }

  void parse_material(std::string_view rest) {
    const auto f = detail::split_fields(rest);
    expect_fields(f, 9, "material ': dr dg db  sr sg sb  er eg eb'");
    Material m;
    m.diffuse = vec<float>(f, 0, "material");
    m.reflective = vec<float>(f, 3, "material");
    m.emissive = vec<float>(f, 6, "material");
    mesh_.materials.push_back(m);
  }

  void parse_face(std::string_view line) {
    const auto f = detail::split_fields(line);
    if (f.size() != 4 && f.size() != 5)
      fail(line_, "face needs 3 or 4 vertex indices and a material index, got " +
                      std::to_string(f.size()) + " fields");
    Face face;
    face.count = static_cast<int>(f.size()) - 1;
    const long nv = static_cast<long>(mesh_.positions.size());
    for (int k = 0; k < face.count; ++k) {
      const long index = number<long>(f[k], "face");
      if (index < 0 || index >= nv)
        fail(line_, "vertex index " + std::to_string(index) + " out of range [0, " +
                        std::to_string(nv) + ")");
      face.v[k] = static_cast<int>(index);
    }
    const long material = number<long>(f.back(), "face");
    const long nm = static_cast<long>(mesh_.materials.size());
    // -1 is a face without material (Face::material, scene/mesh.hpp), as the format allows.
    if (material < -1 || material >= nm)
      fail(line_, "material index " + std::to_string(material) + " out of range [-1, " +
                      std::to_string(nm) + ")");
    face.material = static_cast<int>(material);
    mesh_.faces.push_back(face);
  }

  const std::string& path_;
  Mesh mesh_;
  Section section_ = Section::kVertices;
  long line_ = 0;
};

}  // namespace

Mesh read_bakeshop(const std::string& path) {
  const std::string text = detail::read_text_file(path);
  return BakeshopParser(path).parse(text);
}

}  // namespace rtmini
