#include "rtmini/io/bakeshop_binary.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <type_traits>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/text_fields.hpp"

namespace rtmini {
namespace {

constexpr char kMagic[4] = {'B', 'S', 'B', '1'};
constexpr std::uint32_t kShared = 1u << 0;
constexpr std::uint32_t kHalfColor = 1u << 1;
constexpr std::uint32_t kPos64 = 1u << 2;
constexpr std::uint32_t kHemisphere = 1u << 3;  // ViewpointColors::hemisphere
constexpr std::uint32_t kKnownFlags = kShared | kHalfColor | kPos64 | kHemisphere;
constexpr std::size_t kHeaderBytes = 64;
constexpr std::size_t kMaterialFloats = 12;
constexpr std::size_t kFaceInts = 6;
constexpr float kHalfMax = 65504.f;

template <class To, class From>
To bits_of(From value) {
  static_assert(sizeof(To) == sizeof(From));
  To out;
  std::memcpy(&out, &value, sizeof(out));
  return out;
}

// IEEE binary16 with round-to-nearest-even; finite inputs are clamped to the half range (a
// colour brighter than 65504 saturates rather than becoming inf, which the reader rejects).
// Written out instead of using a compiler's _Float16: identical bits on every host.
std::uint16_t float_to_half(float f) {
  f = f > kHalfMax ? kHalfMax : (f < -kHalfMax ? -kHalfMax : f);
  const std::uint32_t x = bits_of<std::uint32_t>(f);
  const std::uint16_t sign = static_cast<std::uint16_t>((x >> 16) & 0x8000u);
  const std::uint32_t abs = x & 0x7fffffffu;
  if (abs >= 0x38800000u) {  // >= 2^-14: a normal half
    const std::uint32_t mant = abs & 0x7fffffu;
    std::uint32_t h = ((((abs >> 23) - 127u + 15u)) << 10) | (mant >> 13);
    const std::uint32_t rest = mant & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) ++h;
    return static_cast<std::uint16_t>(sign | h);
  }
  // Subnormal halves are multiples of 2^-24; nearbyint rounds ties to even.
  const float a = bits_of<float>(abs);
  return static_cast<std::uint16_t>(sign |
                                    static_cast<std::uint16_t>(std::nearbyint(a * 16777216.f)));
}

float half_to_float(std::uint16_t h) {
  const std::uint32_t sign = static_cast<std::uint32_t>(h & 0x8000u) << 16;
  const std::uint32_t e = (h >> 10) & 0x1fu;
  const std::uint32_t m = h & 0x3ffu;
  if (e == 0) {
    const float v = static_cast<float>(m) / 16777216.f;
    return sign ? -v : v;
  }
  if (e == 31) return std::numeric_limits<float>::infinity();  // rejected by the reader
  return bits_of<float>(sign | ((e - 15u + 127u) << 23) | (m << 13));
}

// Little-endian serialisation independent of the host byte order. `base` is the file offset of
// the first byte written: sections align to 8-byte offsets of the file, not of this buffer.
class ByteWriter {
 public:
  explicit ByteWriter(std::uint64_t base = 0) : base_(base) {}
  template <class T>
  void put(T value) {
    using U = std::conditional_t<
        sizeof(T) == 8, std::uint64_t,
        std::conditional_t<sizeof(T) == 4, std::uint32_t,
                           std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint8_t>>>;
    const U u = bits_of<U>(value);
    for (std::size_t b = 0; b < sizeof(T); ++b)
      out_.push_back(static_cast<char>((u >> (8 * b)) & 0xffu));
  }
  void put_bytes(const char* data, std::size_t n) { out_.append(data, n); }
  void put_bytes(const std::string& bytes) { out_.append(bytes); }
  void align8() {
    while ((base_ + out_.size()) % 8 != 0) out_.push_back('\0');
  }
  void patch_u64(std::size_t at, std::uint64_t value) {
    for (std::size_t b = 0; b < 8; ++b)
      out_[at + b] = static_cast<char>((value >> (8 * b)) & 0xffu);
  }
  std::size_t size() const { return out_.size(); }
  const std::string& bytes() const { return out_; }

 private:
  std::uint64_t base_;
  std::string out_;
};

class ByteReader {
 public:
  ByteReader(const std::string& path, std::string_view data) : path_(path), data_(data) {}

  [[noreturn]] void fail(const std::string& reason) const {
    throw InputError(path_, 0, reason + " (at byte " + std::to_string(pos_) + ")");
  }

  template <class T>
  T get() {
    using U = std::conditional_t<
        sizeof(T) == 8, std::uint64_t,
        std::conditional_t<sizeof(T) == 4, std::uint32_t,
                           std::conditional_t<sizeof(T) == 2, std::uint16_t, std::uint8_t>>>;
    if (data_.size() - pos_ < sizeof(T)) fail("file truncated");
    U u = 0;
    for (std::size_t b = 0; b < sizeof(T); ++b)
      u |= static_cast<U>(static_cast<unsigned char>(data_[pos_ + b])) << (8 * b);
    pos_ += sizeof(T);
    return bits_of<T>(u);
  }

  template <class T>
  T finite(const char* what) {
    const T v = get<T>();
    if (!std::isfinite(v)) fail(std::string("non-finite value in ") + what);
    return v;
  }

  void align8() {
    const std::size_t next = (pos_ + 7) / 8 * 8;
    if (next > data_.size()) fail("file truncated");
    pos_ = next;
  }
  // Rejects counts that cannot fit in the remaining bytes before allocating for them.
  void require(std::uint64_t count, std::uint64_t bytes_each, const char* what) {
    if (bytes_each != 0 && count > (data_.size() - pos_) / bytes_each)
      fail(std::string("file too short for ") + std::to_string(count) + " " + what);
  }
  std::string bytes(std::size_t n) {
    if (data_.size() - pos_ < n) fail("file truncated");
    std::string s(data_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  std::size_t pos() const { return pos_; }
  std::size_t size() const { return data_.size(); }

 private:
  const std::string& path_;
  std::string_view data_;
  std::size_t pos_ = 0;
};

bool same_bits(const Vec3f& a, const Vec3f& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; }

bool float_exact(double v) { return static_cast<double>(static_cast<float>(v)) == v; }

}  // namespace

std::string format_bakeshop_binary_tail(const Mesh& mesh, std::uint64_t colors_end) {
  ByteWriter w(colors_end);
  w.align8();
  for (const Material& m : mesh.materials) {
    for (const Vec3f& v : {m.diffuse, m.reflective, m.emissive}) {
      w.put(v.x);
      w.put(v.y);
      w.put(v.z);
    }
    w.put(m.shininess);
    w.put(m.ior);
    w.put(m.opacity);
  }
  w.align8();
  for (const Face& f : mesh.faces) {
    for (int k = 0; k < 4; ++k) w.put<std::int32_t>(k < f.count ? f.v[k] : -1);
    w.put<std::int32_t>(f.material);
    w.put<std::int32_t>(f.object);
  }
  w.align8();
  for (const std::string& name : mesh.objects) {
    w.put(static_cast<std::uint32_t>(name.size()));
    w.put_bytes(name.data(), name.size());
  }
  w.align8();
  return w.bytes();
}

void write_bakeshop_binary(const std::string& path, const Mesh& mesh,
                           const BakeshopBinaryOptions& options) {
  const std::size_t nv = mesh.positions.size();
  const ViewpointColors& vp = mesh.viewpoints;
  const bool has_views = !vp.offsets.empty();
  auto count_of = [&](std::size_t i) { return has_views ? vp.offsets[i + 1] - vp.offsets[i] : 0; };

  // Shared set: every vertex with viewpoints repeats the first such vertex's directions (the
  // baker's Fibonacci set): stored once instead of once per vertex, the bulk of a .bsb otherwise.
  std::size_t ref = nv;
  for (std::size_t i = 0; i < nv && ref == nv; ++i)
    if (count_of(i) > 0) ref = i;
  bool shared = ref < nv;
  for (std::size_t i = 0; shared && i < nv; ++i) {
    const std::size_t n = count_of(i);
    if (n == 0) continue;
    if (n != count_of(ref)) {
      shared = false;
      break;
    }
    for (std::size_t k = 0; k < n && shared; ++k)
      shared = same_bits(vp.dirs[vp.offsets[i] + k], vp.dirs[vp.offsets[ref] + k]);
  }
  bool pos32 = true;
  for (const Vec3d& p : mesh.positions)
    pos32 = pos32 && float_exact(p.x) && float_exact(p.y) && float_exact(p.z);

  std::vector<std::uint8_t> uniform(nv, 0);
  std::uint64_t colors = 0;
  for (std::size_t i = 0; i < nv; ++i) {
    const std::size_t n = count_of(i);
    if (n == 0) continue;
    bool same = true;
    for (std::size_t k = 1; k < n && same; ++k)
      same = same_bits(vp.colors[vp.offsets[i] + k], vp.colors[vp.offsets[i]]);
    uniform[i] = same ? 1 : 0;
    colors += same ? 1 : n;
  }
  const std::uint64_t dirs = shared ? count_of(ref) : vp.dirs.size();

  ByteWriter w;
  w.put_bytes(kMagic, 4);
  w.put<std::uint32_t>((shared ? kShared : 0u) | (options.half_colors ? kHalfColor : 0u) |
                       (pos32 ? 0u : kPos64) | (vp.hemisphere ? kHemisphere : 0u));
  w.put<std::uint64_t>(nv);
  w.put<std::uint64_t>(mesh.materials.size());
  w.put<std::uint64_t>(mesh.faces.size());
  w.put<std::uint64_t>(mesh.objects.size());
  w.put<std::uint64_t>(dirs);
  w.put<std::uint64_t>(colors);
  w.put<std::uint64_t>(0);  // file size, patched below

  for (const Vec3d& p : mesh.positions) {
    if (pos32) {
      w.put(static_cast<float>(p.x));
      w.put(static_cast<float>(p.y));
      w.put(static_cast<float>(p.z));
    } else {
      w.put(p.x);
      w.put(p.y);
      w.put(p.z);
    }
  }
  w.align8();
  for (std::size_t i = 0; i < nv; ++i) w.put(static_cast<std::uint32_t>(count_of(i)));
  w.align8();
  for (std::size_t i = 0; i < nv; ++i) w.put(uniform[i]);
  w.align8();
  const std::size_t dir_begin = shared ? vp.offsets[ref] : 0;
  for (std::size_t k = 0; k < dirs; ++k) {
    const Vec3f& d = vp.dirs[dir_begin + k];
    w.put(d.x);
    w.put(d.y);
    w.put(d.z);
  }
  w.align8();
  for (std::size_t i = 0; i < nv; ++i) {
    const std::size_t n = count_of(i) == 0 ? 0 : (uniform[i] ? 1 : count_of(i));
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3f& c = vp.colors[vp.offsets[i] + k];
      for (const float v : {c.x, c.y, c.z}) {
        if (options.half_colors) {
          w.put(float_to_half(v));
        } else {
          w.put(v);
        }
      }
    }
  }
  w.put_bytes(format_bakeshop_binary_tail(mesh, w.size()));
  // The size field is known only now; the reader compares it with the file's real size first,
  // so a truncated copy fails with one clear message instead of somewhere in a section.
  w.patch_u64(56, w.size());
  write_text_atomic(path, w.bytes());
}

Mesh read_bakeshop_binary(const std::string& path) {
  const std::string data = detail::read_text_file(path);
  ByteReader r(path, data);
  if (data.size() < kHeaderBytes || std::memcmp(data.data(), kMagic, 4) != 0)
    r.fail("not a binary Bake Shop map (expected magic \"BSB1\" and a 64-byte header)");
  r.bytes(4);
  // Unknown flags are refused, not ignored: a later format revision that sets one changes the
  // layout, and reading past it would give a wrong mesh rather than an error.
  const std::uint32_t flags = r.get<std::uint32_t>();
  if (flags & ~kKnownFlags) r.fail("unknown flags " + std::to_string(flags));
  const std::uint64_t nv = r.get<std::uint64_t>();
  const std::uint64_t nm = r.get<std::uint64_t>();
  const std::uint64_t nf = r.get<std::uint64_t>();
  const std::uint64_t no = r.get<std::uint64_t>();
  const std::uint64_t nd = r.get<std::uint64_t>();
  const std::uint64_t nc = r.get<std::uint64_t>();
  const std::uint64_t size = r.get<std::uint64_t>();
  if (size != data.size())
    r.fail("file is " + std::to_string(data.size()) + " bytes but its header says " +
           std::to_string(size) + " (truncated or corrupt)");
  const bool shared = flags & kShared;
  const bool half = flags & kHalfColor;
  const bool pos64 = flags & kPos64;

  Mesh mesh;
  // Every count from the header is checked against the bytes left (require) before anything is
  // allocated for it: a corrupt or hostile file fails with InputError, never std::bad_alloc.
  r.require(nv, pos64 ? 24 : 12, "vertices");
  mesh.positions.resize(nv);
  for (Vec3d& p : mesh.positions) {
    for (double* c : {&p.x, &p.y, &p.z})
      *c = pos64 ? r.finite<double>("a position") : r.finite<float>("a position");
  }
  r.align8();
  r.require(nv, 5, "vertices");
  std::vector<std::uint32_t> counts(nv);
  for (std::uint32_t& n : counts) n = r.get<std::uint32_t>();
  r.align8();
  std::vector<std::uint8_t> uniform(nv);
  std::uint64_t expect_dirs = 0;
  std::uint64_t expect_colors = 0;
  for (std::size_t i = 0; i < nv; ++i) {
    uniform[i] = r.get<std::uint8_t>();
    if (uniform[i] > 1 || (uniform[i] == 1 && counts[i] == 0))
      r.fail("vertex " + std::to_string(i) + ": invalid uniform flag");
    if (shared && counts[i] != 0 && counts[i] != nd)
      r.fail("vertex " + std::to_string(i) + " has " + std::to_string(counts[i]) +
             " viewpoints but the shared set has " + std::to_string(nd));
    expect_dirs += counts[i];
    expect_colors += counts[i] == 0 ? 0 : (uniform[i] ? 1 : counts[i]);
  }
  if (!shared && nd != expect_dirs)
    r.fail("header says " + std::to_string(nd) + " directions, the vertex counts sum to " +
           std::to_string(expect_dirs));
  if (nc != expect_colors)
    r.fail("header says " + std::to_string(nc) + " colours, the vertex counts need " +
           std::to_string(expect_colors));
  r.align8();
  r.require(nd, 12, "directions");
  std::vector<Vec3f> dirs(nd);
  for (Vec3f& d : dirs)
    d = {r.finite<float>("a direction"), r.finite<float>("a direction"),
         r.finite<float>("a direction")};
  r.align8();
  r.require(nc, half ? 6 : 12, "colours");
  std::vector<Vec3f> colors(nc);
  for (Vec3f& c : colors) {
    for (float* v : {&c.x, &c.y, &c.z}) {
      *v = half ? half_to_float(r.get<std::uint16_t>()) : r.get<float>();
      if (!std::isfinite(*v)) r.fail("non-finite value in a colour");
    }
  }

  // Expanded to the in-memory form (every vertex its own directions and colours), so the rest of
  // the code sees the same Mesh as from a .bs file; the compaction is the file's business only.
  if (expect_dirs > 0) {
    ViewpointColors& vp = mesh.viewpoints;
    vp.hemisphere = flags & kHemisphere;
    vp.offsets.resize(nv + 1);
    vp.dirs.reserve(expect_dirs);
    vp.colors.reserve(expect_dirs);
    std::size_t next_dir = 0;
    std::size_t next_color = 0;
    vp.offsets[0] = 0;
    for (std::size_t i = 0; i < nv; ++i) {
      for (std::uint32_t k = 0; k < counts[i]; ++k) {
        vp.dirs.push_back(shared ? dirs[k] : dirs[next_dir++]);
        vp.colors.push_back(colors[next_color + (uniform[i] ? 0 : k)]);
      }
      if (counts[i] > 0) next_color += uniform[i] ? 1 : counts[i];
      vp.offsets[i + 1] = vp.dirs.size();
    }
  }

  r.align8();
  r.require(nm, kMaterialFloats * 4, "materials");
  mesh.materials.resize(nm);
  for (Material& m : mesh.materials) {
    for (Vec3f* v : {&m.diffuse, &m.reflective, &m.emissive})
      *v = {r.finite<float>("a material"), r.finite<float>("a material"),
            r.finite<float>("a material")};
    m.shininess = r.finite<float>("a material");
    m.ior = r.finite<float>("a material");
    m.opacity = r.finite<float>("a material");
  }
  r.align8();
  r.require(nf, kFaceInts * 4, "faces");
  mesh.faces.resize(nf);
  for (std::size_t i = 0; i < nf; ++i) {
    Face& f = mesh.faces[i];
    const std::string where = "face " + std::to_string(i) + ": ";
    for (int k = 0; k < 4; ++k) f.v[k] = r.get<std::int32_t>();
    f.count = f.v[3] == -1 ? 3 : 4;  // the writer's marker for a triangle
    for (int k = 0; k < f.count; ++k)
      if (f.v[k] < 0 || static_cast<std::uint64_t>(f.v[k]) >= nv)
        r.fail(where + "vertex index " + std::to_string(f.v[k]) + " out of range [0, " +
               std::to_string(nv) + ")");
    f.material = r.get<std::int32_t>();
    if (f.material < -1 || (f.material >= 0 && static_cast<std::uint64_t>(f.material) >= nm))
      r.fail(where + "material index " + std::to_string(f.material) + " out of range [-1, " +
             std::to_string(nm) + ")");
    f.object = r.get<std::int32_t>();
    // A file with no object names may still use object 0 (the implicit single object).
    if (f.object < 0 || (no > 0 && static_cast<std::uint64_t>(f.object) >= no) ||
        (no == 0 && f.object != 0))
      r.fail(where + "object index " + std::to_string(f.object) + " out of range");
  }
  r.align8();
  r.require(no, 4, "objects");
  mesh.objects.resize(no);
  for (std::string& name : mesh.objects) name = r.bytes(r.get<std::uint32_t>());
  r.align8();
  if (r.pos() != r.size()) r.fail("unexpected bytes after the objects section");
  return mesh;
}

}  // namespace rtmini
