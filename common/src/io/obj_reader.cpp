// Double positions, as Mesh keeps them (and .bs files): far-off or large scenes lose nothing
// before the upload rounds them to Real. This file holds tinyobjloader's one implementation.
#define TINYOBJLOADER_USE_DOUBLE
#define TINYOBJLOADER_IMPLEMENTATION
#include "rtmini/io/obj_reader.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <thread>
#include <utility>

#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/gltf_reader.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/path.hpp"
#include "rtmini/io/text_fields.hpp"
#include "rtmini/parallel/host_threads.hpp"

namespace rtmini {
namespace {

std::string obj_folder(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

// One pass over the OBJ text. It checks what a reader could otherwise accept silently or crash
// on (field counts, numbers, finiteness, index ranges), every error at its own "file:line", and,
// given a Mesh, reads the geometry in the same pass: positions, texture coordinates, faces
// (quads kept, larger polygons fanned), object names, and the `mtllib`/`usemtl` statements
// whose materials read_obj resolves once the libraries are read. No allocation per line: the
// fields of a line are views into the text, kept in one reused vector.
class ObjScan {
 public:
  // A `usemtl` statement: its name, line, and how many `mtllib` statements came before it
  // (a material is known to a face only when its library was named earlier in the file).
  struct UseMtl {
    std::string name;
    long line = 0;
    std::size_t libraries_before = 0;
    // `usemtlNAME` with no space: it sets the faces' material as before this reader (by that
    // name, -1 when unknown) but is not checked against the libraries.
    bool glued = false;
  };

  // Where a piece of the text starts when read_obj scans a large file in pieces (in parallel):
  // the vertices, texture coordinates and normals defined before it, the lines before it, and
  // whether it continues an earlier piece (its first faces then belong to the object and
  // material that piece ended with, which append() resolves).
  struct Start {
    long nv = 0, nvt = 0, nvn = 0, lines = 0;
    bool continues = false;
  };

  explicit ObjScan(const std::string& path, Mesh* mesh = nullptr) : ObjScan(path, mesh, Start()) {}
  ObjScan(const std::string& path, Mesh* mesh, const Start& start)
      : path_(path),
        mesh_(mesh),
        line_offset_(start.lines),
        nv_(start.nv),
        nvt_(start.nvt),
        nvn_(start.nvn),
        name_(start.continues ? kInherited : "") {}

  void run(std::string_view text) {
    if (mesh_ != nullptr) reserve_for(text);
    detail::LineCursor cursor(text);
    std::string_view raw;
    while (cursor.next(raw)) {
      line_ = line_offset_ + cursor.line_number();
      std::string_view line = raw;
      const std::size_t hash = line.find('#');
      if (hash != std::string_view::npos) line = line.substr(0, hash);
      split_into(line, fields_);
      if (!fields_.empty()) statement(raw);
    }
  }

  // The lines of `text` and the vertices, texture coordinates and normals it defines (lines whose
  // first field is `v`, `vt`, `vn`; in a text without errors each defines one).
  static Start count(std::string_view text) {
    Start start;
    detail::LineCursor cursor(text);
    std::string_view line;
    while (cursor.next(line)) {
      const std::size_t first = line.find_first_not_of(" \t\r");
      if (first == std::string_view::npos || line[first] == '#') continue;
      const std::size_t end = line.find_first_of(" \t\r#", first);
      const std::string_view keyword = line.substr(first, end - first);
      start.nv += keyword == "v";
      start.nvt += keyword == "vt";
      start.nvn += keyword == "vn";
    }
    start.lines = cursor.line_number();
    return start;
  }

  // Takes over the piece scanned after this scan's text (with the Start that count() gave): its
  // geometry joins this scan's mesh, its first faces get the object and material this scan ended
  // with, its `usemtl`/`mtllib` statements follow ours.
  void append(const ObjScan& piece, const Mesh& piece_mesh) {
    const int usemtl_before = static_cast<int>(usemtl_.size());
    std::vector<int> object_of(piece_mesh.objects.size());
    for (std::size_t i = 0; i < object_of.size(); ++i)
      object_of[i] = object_id(piece_mesh.objects[i] == kInherited ? name_ : piece_mesh.objects[i]);
    mesh_->positions.insert(mesh_->positions.end(), piece_mesh.positions.begin(),
                            piece_mesh.positions.end());
    mesh_->texcoords.insert(mesh_->texcoords.end(), piece_mesh.texcoords.begin(),
                            piece_mesh.texcoords.end());
    for (Face face : piece_mesh.faces) {
      face.object = object_of[static_cast<std::size_t>(face.object)];
      face.material = face.material >= 0 ? face.material + usemtl_before : usemtl_before - 1;
      mesh_->faces.push_back(face);
    }
    for (UseMtl use : piece.usemtl_) {
      use.libraries_before += mtllib_names_.size();
      usemtl_.push_back(std::move(use));
    }
    mtllib_names_.insert(mtllib_names_.end(), piece.mtllib_names_.begin(),
                         piece.mtllib_names_.end());
    for (const std::string& mtl : piece.mtl_files_)
      if (std::find(mtl_files_.begin(), mtl_files_.end(), mtl) == mtl_files_.end())
        mtl_files_.push_back(mtl);
    if (missing_mtl_line_ == 0) {
      missing_mtl_line_ = piece.missing_mtl_line_;
      missing_mtl_ = piece.missing_mtl_;
    }
    if (piece.name_ != kInherited) name_ = piece.name_;
    object_ = -1;
    nv_ = piece.nv_;
    nvt_ = piece.nvt_;
    nvn_ = piece.nvn_;
  }

  // After the whole text: a missing library matters only when a face asks for a material from it
  // (the shared dragon.obj names a dragon.mtl that does not exist and uses none).
  void check_libraries() {
    const bool uses_materials =
        std::any_of(usemtl_.begin(), usemtl_.end(), [](const UseMtl& u) { return !u.glued; });
    if (missing_mtl_line_ > 0 && uses_materials) {
      line_ = missing_mtl_line_;
      fail("cannot open material library '" + missing_mtl_ + "'");
    }
  }

  const std::vector<UseMtl>& usemtl() const { return usemtl_; }
  const std::vector<std::string>& mtl_files() const { return mtl_files_; }
  const std::vector<std::string>& image_files() const { return image_files_; }
  // The file names of each `mtllib` statement, split as OBJ writers escape them ("a\ b.mtl").
  const std::vector<std::vector<std::string>>& mtllib_names() const { return mtllib_names_; }

  // A material library: the numbers of the statements rtmini reads (colours Ka Kd Ks Ke Tf,
  // scalars Ns Ni d Tr), so that a bad value is reported at its own file and line, and the
  // image maps (map_Kd map_Ks map_bump bump norm disp), each decoded once here so that a
  // missing or broken image is reported at the line that names it.
  void run_mtl(std::string_view text) {
    detail::LineCursor cursor(text);
    std::string_view line;
    while (cursor.next(line)) {
      line_ = cursor.line_number();
      const std::size_t hash = line.find('#');
      if (hash != std::string_view::npos) line = line.substr(0, hash);
      split_into(line, fields_);
      if (!fields_.empty()) mtl_statement(fields_);
    }
  }

 private:
  // Room for the vertices, texture coordinates and faces the text holds (lines starting "v ",
  // "vt ", "f "): the arrays grow once instead of being copied at every doubling.
  void reserve_for(std::string_view text) {
    std::size_t v = 0, vt = 0, f = 0;
    for (std::size_t i = 0; i + 2 < text.size();) {
      const char c0 = text[i], c1 = text[i + 1];
      v += c0 == 'v' && c1 == ' ';
      vt += c0 == 'v' && c1 == 't' && text[i + 2] == ' ';
      f += c0 == 'f' && c1 == ' ';
      const std::size_t end = text.find('\n', i);
      if (end == std::string_view::npos) break;
      i = end + 1;
    }
    mesh_->positions.reserve(v);
    mesh_->texcoords.reserve(vt);
    mesh_->faces.reserve(f);
  }

  // Splits on spaces, tabs and '\r' (CRLF files), as detail::split_fields, into a reused vector.
  static void split_into(std::string_view line, std::vector<std::string_view>& fields) {
    fields.clear();
    const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_space(line[i])) ++i;
      if (i > start) fields.push_back(line.substr(start, i - start));
    }
  }

  void statement(std::string_view raw) {
    const std::vector<std::string_view>& f = fields_;
    if (f[0] == "v") {
      if (f.size() != 4 && f.size() != 5 && f.size() != 7)
        fail("vertex needs 3 coordinates (optionally w, or r g b), got " +
             std::to_string(f.size() - 1) + " fields");
      double xyz[3];
      for (std::size_t i = 1; i < f.size(); ++i) {
        const double value = number(f[i], "vertex");
        if (i <= 3) xyz[i - 1] = value;
      }
      if (mesh_ != nullptr) mesh_->positions.emplace_back(xyz[0], xyz[1], xyz[2]);
      ++nv_;
    } else if (f[0] == "vt") {
      if (f.size() < 2 || f.size() > 4) fail("texture coordinate needs 1 to 3 fields");
      double uv[2] = {0.0, 0.0};  // a missing v is 0
      for (std::size_t i = 1; i < f.size(); ++i) {
        const double value = number(f[i], "texture coordinate");
        if (i <= 2) uv[i - 1] = value;
      }
      if (mesh_ != nullptr)
        mesh_->texcoords.push_back({static_cast<float>(uv[0]), static_cast<float>(uv[1])});
      ++nvt_;
    } else if (f[0] == "vn") {
      if (f.size() != 4) fail("normal needs 3 fields, got " + std::to_string(f.size() - 1));
      for (std::size_t i = 1; i < f.size(); ++i) (void)number(f[i], "normal");
      ++nvn_;
    } else if (f[0] == "f") {
      if (f.size() < 4) fail("face needs at least 3 vertices, got " + std::to_string(f.size() - 1));
      face(f);
    } else if (f[0] == "mtllib") {
      mtllib(f, raw);
    } else if (f[0] == "usemtl") {
      if (f.size() != 2) fail("usemtl needs exactly one material name");
      usemtl_.push_back({std::string(f[1]), line_, mtllib_names_.size()});
    } else if (f[0].substr(0, 6) == "usemtl") {
      usemtl_.push_back({std::string(f[0].substr(6)), line_, mtllib_names_.size(), true});
    } else if (is_name_statement(raw, 'g')) {
      group(raw);
    } else if (is_name_statement(raw, 'o')) {
      // The object's name is the rest of the line, as written.
      name_ = std::string(statement_rest(raw));
      object_ = -1;
    }
  }

  // `g`/`o` followed by a space or tab (a bare "g" names nothing and is ignored).
  static bool is_name_statement(std::string_view raw, char keyword) {
    const std::size_t k = raw.find_first_not_of(" \t");
    return k != std::string_view::npos && k + 1 < raw.size() && raw[k] == keyword &&
           (raw[k + 1] == ' ' || raw[k + 1] == '\t');
  }
  // What follows the keyword's one-character name and its separator.
  static std::string_view statement_rest(std::string_view raw) {
    return raw.substr(raw.find_first_not_of(" \t") + 2);
  }

  // `g a b`: the group names joined by one space (one object per distinct list); `g ` alone
  // returns to the unnamed object.
  void group(std::string_view raw) {
    std::vector<std::string_view> names;
    split_into(statement_rest(raw), names);
    name_.clear();
    for (std::size_t i = 0; i < names.size(); ++i) {
      if (i > 0) name_ += ' ';
      name_ += names[i];
    }
    object_ = -1;
  }

  void mtllib(const std::vector<std::string_view>& f, std::string_view raw) {
    if (f.size() < 2) fail("mtllib without a file name");
    for (std::size_t i = 1; i < f.size(); ++i) {
      const std::string mtl = obj_folder(path_) + "/" + std::string(f[i]);
      if (std::ifstream(mtl)) {
        if (std::find(mtl_files_.begin(), mtl_files_.end(), mtl) == mtl_files_.end())
          mtl_files_.push_back(mtl);
      } else if (missing_mtl_line_ == 0) {
        missing_mtl_line_ = line_;
        missing_mtl_ = mtl;
      }
    }
    // File names split on spaces, a backslash escaping the next character (writers escape
    // spaces in names this way); the comment is part of the raw line, as for object names.
    std::vector<std::string> names(1);
    bool escaped = false;
    const std::size_t keyword = static_cast<std::size_t>(f[0].data() - raw.data());
    const std::string_view rest = raw.substr(keyword + f[0].size() + 1);
    for (const char c : rest) {
      if (!escaped && c == '\\') {
        escaped = true;
        continue;
      }
      if (!escaped && c == ' ') {
        if (!names.back().empty()) names.emplace_back();
      } else {
        names.back() += c;
      }
      escaped = false;
    }
    if (names.back().empty()) names.pop_back();
    mtllib_names_.push_back(std::move(names));
  }

  // Checks the face's vertex references and, for a mesh, stores it: up to 4 vertices as one
  // Face, more as a fan from the first vertex (exact for the convex polygons exporters write).
  // Face::material holds the index of the face's `usemtl` statement until read_obj resolves it.
  void face(const std::vector<std::string_view>& f) {
    poly_v_.clear();
    poly_uv_.clear();
    for (std::size_t i = 1; i < f.size(); ++i) face_vertex(f[i]);
    if (mesh_ == nullptr) return;
    if (object_ < 0) object_ = object_id(name_);
    Face face;
    face.material = static_cast<int>(usemtl_.size()) - 1;
    face.object = object_;
    const int n = static_cast<int>(poly_v_.size());
    if (n <= 4) {
      face.count = n;
      std::copy(poly_v_.begin(), poly_v_.end(), face.v.begin());
      std::copy(poly_uv_.begin(), poly_uv_.end(), face.uv.begin());
      mesh_->faces.push_back(face);
      return;
    }
    face.count = 3;
    for (int k = 1; k + 1 < n; ++k) {
      face.v = {poly_v_[0], poly_v_[k], poly_v_[k + 1], -1};
      face.uv = {poly_uv_[0], poly_uv_[k], poly_uv_[k + 1], -1};
      mesh_->faces.push_back(face);
    }
  }

  // The Mesh::objects id of a `g`/`o` name ("" is "default"), added at its first use.
  int object_id(const std::string& name) {
    const std::string& key = name.empty() ? kDefaultObject : name;
    const auto [it, inserted] = object_ids_.emplace(key, static_cast<int>(mesh_->objects.size()));
    if (inserted) mesh_->objects.push_back(key);
    return it->second;
  }

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_, line_, reason);
  }

  static bool is_image_map(std::string_view keyword) {
    return keyword == "map_Kd" || keyword == "map_Ks" || keyword == "map_bump" ||
           keyword == "map_Bump" || keyword == "bump" || keyword == "norm" || keyword == "disp";
  }

  void mtl_statement(const std::vector<std::string_view>& f) {
    if (is_image_map(f[0])) return check_image_map(f);
    const bool colour =
        f[0] == "Ka" || f[0] == "Kd" || f[0] == "Ks" || f[0] == "Ke" || f[0] == "Tf";
    const bool scalar = f[0] == "Ns" || f[0] == "Ni" || f[0] == "d" || f[0] == "Tr";
    if (!colour && !scalar) return;
    if (colour && f.size() > 1 && (f[1] == "spectral" || f[1] == "xyz")) return;
    if (f.size() < 2) fail(std::string(f[0]) + " needs a value");
    const std::string what = "material statement " + std::string(f[0]);
    for (std::size_t i = 1; i < f.size(); ++i) (void)number(f[i], what.c_str());
  }

  // `keyword [-option values...] file`: tinyobjloader parses the options (-bm is kept as the
  // map's scale, the others are accepted and ignored); the file is the last field.
  void check_image_map(const std::vector<std::string_view>& f) {
    if (f.size() < 2) fail(std::string(f[0]) + " needs an image file");
    const std::string name(f.back());
    if (name[0] == '-') fail(std::string(f[0]) + " needs an image file after its options");
    const std::string file = obj_folder(path_) + "/" + name;
    if (lower_extension(file) != ".png")
      fail("image map '" + name + "' is not a PNG file (only PNG maps are read)");
    if (std::find(image_files_.begin(), image_files_.end(), file) != image_files_.end()) return;
    try {
      (void)read_png_data(file);
    } catch (const std::exception& e) {
      fail("cannot read image map '" + name + "': " + e.what());
    }
    image_files_.push_back(file);
  }

  // A finite number that stays finite in Real, else an error naming the field.
  double number(std::string_view field, const char* what) const {
    const auto value = detail::parse_number<double>(field);
    if (!value) fail("invalid number '" + std::string(field) + "' in " + what);
    if (!std::isfinite(*value)) fail("non-finite value '" + std::string(field) + "' in " + what);
    if (!detail::fits_real(*value))
      fail("value '" + std::string(field) + "' in " + what + " is beyond the " +
           detail::real_range_name() + " range (non-finite once uploaded)");
    // The value stored is tinyobjloader's reading of the checked number (off from the correctly
    // rounded one by up to 2 ulp, the same float): meshes and the .bs files made from them keep
    // the bytes they had when tinyobjloader parsed the geometry.
    double stored = *value;
    if (!tinyobj::tryParseDouble(field.data(), field.data() + field.size(), &stored))
      stored = *value;
    return stored;
  }

  // A 1-based (or negative, relative to the end) index checked against the `count` defined so
  // far, returned 0-based.
  int index(std::string_view field, long count, const char* what) const {
    const std::optional<long> value = parse_index(field);
    if (!value) fail("invalid " + std::string(what) + " index '" + std::string(field) + "'");
    if (*value == 0) fail(std::string(what) + " index 0 is invalid (OBJ indices start at 1)");
    if (*value > count || -*value > count)
      fail(std::string(what) + " index " + std::to_string(*value) + " out of range (" +
           std::to_string(count) + " defined so far)");
    return static_cast<int>(*value > 0 ? *value - 1 : count + *value);
  }

  // Most indices are a few plain digits: read those directly, anything else (a sign, a long or
  // malformed number) as detail::parse_number reads it.
  static std::optional<long> parse_index(std::string_view field) {
    if (field.empty() || field.size() > 9) return detail::parse_number<long>(field);
    long value = 0;
    for (const char c : field) {
      if (c < '0' || c > '9') return detail::parse_number<long>(field);
      value = 10 * value + (c - '0');
    }
    return value;
  }

  // `v`, `v/vt`, `v//vn` or `v/vt/vn`: appends the vertex and texture-coordinate indices.
  void face_vertex(std::string_view ref) {
    const std::size_t s1 = ref.find('/');
    poly_v_.push_back(index(ref.substr(0, s1), nv_, "vertex"));
    poly_uv_.push_back(-1);
    if (s1 == std::string_view::npos) return;
    const std::string_view rest = ref.substr(s1 + 1);
    const std::size_t s2 = rest.find('/');
    const std::string_view vt = rest.substr(0, s2);
    if (!vt.empty()) poly_uv_.back() = index(vt, nvt_, "texture coordinate");
    if (s2 == std::string_view::npos) return;
    const std::string_view vn = rest.substr(s2 + 1);
    if (vn.empty() || vn.find('/') != std::string_view::npos)
      fail("malformed face vertex '" + std::string(ref) + "'");
    (void)index(vn, nvn_, "normal");
  }

  // The name a continuing piece's faces have until its first `g`/`o` (no line holds a '\n').
  static inline const std::string kInherited = "\n";
  static inline const std::string kDefaultObject = "default";

  const std::string& path_;
  Mesh* mesh_;
  long line_offset_ = 0;
  long line_ = 0;
  long nv_ = 0, nvt_ = 0, nvn_ = 0;
  std::vector<std::string_view> fields_;
  std::vector<int> poly_v_, poly_uv_;
  std::string name_;  // the current `g`/`o` name ("" until one is given)
  int object_ = -1;   // its Mesh::objects id, -1 until a face under it is stored
  std::map<std::string, int> object_ids_;
  std::vector<UseMtl> usemtl_;
  std::vector<std::vector<std::string>> mtllib_names_;
  std::vector<std::string> mtl_files_;
  std::vector<std::string> image_files_;
  long missing_mtl_line_ = 0;
  std::string missing_mtl_;
};

// `text` cut into about n pieces of whole lines.
std::vector<std::string_view> split_at_lines(std::string_view text, std::size_t n) {
  std::vector<std::string_view> pieces;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= n && begin < text.size(); ++k) {
    std::size_t end = std::max(begin, text.size() / n * k);
    end = k == n ? std::string_view::npos : text.find('\n', end);
    end = end == std::string_view::npos ? text.size() : end + 1;
    pieces.push_back(text.substr(begin, end - begin));
    begin = end;
  }
  return pieces;
}

// Scans the OBJ text into `mesh`, in pieces of about piece_bytes (at most max_pieces, one thread
// each) joined in file order: the same Mesh and the same first error as one pass.
ObjScan scan_obj(const std::string& path, std::string_view text, Mesh& mesh,
                 std::size_t piece_bytes, std::size_t max_pieces) {
  const std::size_t n = std::min(std::max<std::size_t>(text.size() / piece_bytes, 1), max_pieces);
  ObjScan scan(path, &mesh);
  const std::vector<std::string_view> pieces = split_at_lines(text, n);
  if (pieces.size() <= 1) {
    scan.run(text);
    return scan;
  }
  // Where each piece starts: what the pieces before it define.
  std::vector<ObjScan::Start> starts(pieces.size());
  on_threads(pieces.size(), [&](std::size_t i) { starts[i] = ObjScan::count(pieces[i]); });
  ObjScan::Start at;
  for (ObjScan::Start& piece : starts) {
    const ObjScan::Start defined = piece;
    piece = at;
    at = {at.nv + defined.nv, at.nvt + defined.nvt, at.nvn + defined.nvn, at.lines + defined.lines,
          true};
  }
  std::vector<Mesh> meshes(pieces.size() - 1);
  std::vector<std::unique_ptr<ObjScan>> scans;
  for (std::size_t i = 1; i < pieces.size(); ++i)
    scans.push_back(std::make_unique<ObjScan>(path, &meshes[i - 1], starts[i]));
  std::vector<std::exception_ptr> errors(pieces.size());
  on_threads(pieces.size(), [&](std::size_t i) {
    try {
      if (i == 0)
        scan.run(pieces[0]);
      else
        scans[i - 1]->run(pieces[i]);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (const std::exception_ptr& error : errors)
    if (error) std::rethrow_exception(error);
  std::size_t faces = mesh.faces.size();
  for (const Mesh& m : meshes) faces += m.faces.size();
  mesh.positions.reserve(static_cast<std::size_t>(at.nv));
  mesh.texcoords.reserve(static_cast<std::size_t>(at.nvt));
  mesh.faces.reserve(faces);
  for (std::size_t i = 1; i < pieces.size(); ++i) scan.append(*scans[i - 1], meshes[i - 1]);
  return scan;
}

// An MTL map name resolved against the library's folder (the OBJ's, where tinyobjloader
// looks for libraries); empty stays empty.
std::string map_path(const std::string& folder, const std::string& name) {
  return name.empty() ? name : folder + "/" + name;
}

Material to_material(const tinyobj::material_t& m, const std::string& folder) {
  const auto v = [](const tinyobj::real_t* c) {
    return Vec3f(static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]));
  };
  Material out;
  out.name = m.name;
  out.diffuse = v(m.diffuse);
  out.reflective = v(m.specular);
  out.emissive = v(m.emission);
  out.shininess = static_cast<float>(m.shininess);
  out.ior = static_cast<float>(m.ior);
  out.opacity = static_cast<float>(m.dissolve);
  out.maps.diffuse = map_path(folder, m.diffuse_texname);
  out.maps.specular = map_path(folder, m.specular_texname);
  out.maps.normal = map_path(folder, m.normal_texname);
  out.maps.bump = map_path(folder, m.bump_texname);
  out.maps.displacement = map_path(folder, m.displacement_texname);
  out.maps.bump_scale = static_cast<float>(m.bump_texopt.bump_multiplier);
  out.maps.displacement_scale = static_cast<float>(m.displacement_texopt.bump_multiplier);
  return out;
}

bool material_is_finite(const Material& m) {
  return is_finite(m.diffuse) && is_finite(m.reflective) && is_finite(m.emissive) &&
         std::isfinite(m.shininess) && std::isfinite(m.ior) && std::isfinite(m.opacity) &&
         std::isfinite(m.maps.bump_scale) && std::isfinite(m.maps.displacement_scale);
}

// The materials of the libraries an OBJ names, read as tinyobjloader reads them: of each
// `mtllib` statement's files, the first that was not read before and opens; a name keeps its
// first definition.
struct MaterialLibraries {
  std::vector<tinyobj::material_t> materials;
  std::map<std::string, int> ids;
  std::vector<std::size_t> count_after;  // materials.size() after each `mtllib` statement
};

MaterialLibraries read_material_libraries(const std::string& folder, const ObjScan& scan) {
  MaterialLibraries out;
  std::set<std::string> read;
  for (const std::vector<std::string>& names : scan.mtllib_names()) {
    for (const std::string& name : names) {
      if (read.count(name) != 0) continue;
      const std::string file = folder + "/" + name;
      if (!std::ifstream(file)) continue;
      std::istringstream text(detail::read_text_file(file));
      std::string warnings, errors;
      tinyobj::LoadMtl(&out.ids, &out.materials, &text, &warnings, &errors);
      read.insert(name);
      break;
    }
    out.count_after.push_back(out.materials.size());
  }
  return out;
}

// The material id of each `usemtl` statement: a material counts only when its library was named
// before the statement (as a reader going through the file once sees it), else -1.
std::vector<int> usemtl_material_ids(const std::vector<ObjScan::UseMtl>& usemtl,
                                     const MaterialLibraries& libraries) {
  std::vector<int> ids;
  for (const ObjScan::UseMtl& use : usemtl) {
    const auto it = libraries.ids.find(use.name);
    const bool known_then =
        it != libraries.ids.end() && use.libraries_before > 0 &&
        static_cast<std::size_t>(it->second) < libraries.count_after[use.libraries_before - 1];
    ids.push_back(known_then ? it->second : -1);
  }
  return ids;
}

}  // namespace

namespace detail {

Mesh read_obj(const std::string& path, std::size_t piece_bytes, std::size_t max_pieces) {
  Mesh mesh;
  const std::string text = read_text_file(path);
  ObjScan scan = scan_obj(path, text, mesh, piece_bytes, max_pieces);
  scan.check_libraries();
  for (const std::string& mtl : scan.mtl_files()) ObjScan(mtl).run_mtl(detail::read_text_file(mtl));

  const MaterialLibraries libraries = read_material_libraries(obj_folder(path), scan);
  for (const tinyobj::material_t& m : libraries.materials) {
    mesh.materials.push_back(to_material(m, obj_folder(path)));
    if (!material_is_finite(mesh.materials.back()))
      throw InputError(path, 0, "material '" + m.name + "' has a non-finite value");
  }
  for (const ObjScan::UseMtl& use : scan.usemtl()) {
    if (use.glued) continue;
    const bool known = std::any_of(mesh.materials.begin(), mesh.materials.end(),
                                   [&use](const Material& m) { return m.name == use.name; });
    if (!known)
      throw InputError(path, use.line, "material '" + use.name + "' is not defined in any mtllib");
  }
  // Faces carry the index of their `usemtl` statement until here.
  const std::vector<int> ids = usemtl_material_ids(scan.usemtl(), libraries);
  for (Face& face : mesh.faces)
    if (face.material >= 0) face.material = ids[static_cast<std::size_t>(face.material)];
  return mesh;
}

}  // namespace detail

// Pieces of 256 KiB, one thread each, up to the host's cores (at most 16): the dragon's 3.3 MB
// take about 13 ms on one core of the dev VM, and the CUDA build's host side is otherwise serial.
// RTMINI_OBJ_THREADS=n caps the pieces (1: one pass on the calling thread), for comparisons.
Mesh read_obj(const std::string& path) {
  constexpr std::size_t kPieceBytes = 256 * 1024, kMaxThreads = 16;
  std::size_t threads = std::min<std::size_t>(std::thread::hardware_concurrency(), kMaxThreads);
  if (const char* e = std::getenv("RTMINI_OBJ_THREADS"))
    if (const auto n = detail::parse_number<long>(e); n && *n >= 1)
      threads = static_cast<std::size_t>(*n);
  return detail::read_obj(path, kPieceBytes, std::max<std::size_t>(threads, 1));
}

bool is_gltf_extension(const std::string& ext) { return ext == ".gltf" || ext == ".glb"; }

std::vector<std::string> mesh_files(const std::string& path) {
  if (is_gltf_extension(lower_extension(path))) return gltf_files(path);
  std::vector<std::string> files{path};
  if (lower_extension(path) != ".obj") return files;
  ObjScan scan(path);
  scan.run(detail::read_text_file(path));
  scan.check_libraries();
  files.insert(files.end(), scan.mtl_files().begin(), scan.mtl_files().end());
  for (const std::string& mtl : scan.mtl_files()) {
    ObjScan library(mtl);
    library.run_mtl(detail::read_text_file(mtl));
    files.insert(files.end(), library.image_files().begin(), library.image_files().end());
  }
  return files;
}

Mesh read_mesh(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return read_obj(path);
  if (ext == ".bs") return read_bakeshop(path);
  if (is_gltf_extension(ext)) return flatten_gltf(read_gltf(path));
  throw InputError(path, 0,
                   "unknown mesh format '" + ext + "' (expected .obj, .bs, .gltf or .glb)");
}

}  // namespace rtmini
