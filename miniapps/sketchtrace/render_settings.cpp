#include "render_settings.hpp"

#include <algorithm>
#include <cmath>

#include "rtmini/io/error.hpp"
#include "rtmini/io/scene_settings.hpp"
#include "rtmini/io/text_fields.hpp"

namespace rtmini::sketch {
namespace {

const char* const kAovNames[] = {"depth", "normal", "object", "cost", "edge"};

// Typed access to [settings] with the offending value's line in every error.
class SettingsReader {
 public:
  SettingsReader(const toml::table& t, const std::string& file) : table_(t), file_(file) {}

  // Values copied out of the parsed document lose their source position; keys keep it.
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const {
    long line = 0;
    for (const auto& [k, v] : table_) {
      if (k.str() != key) continue;
      line = k.source().begin.line > 0 ? static_cast<long>(k.source().begin.line)
                                       : static_cast<long>(v.source().begin.line);
    }
    throw InputError(file_, line, "'" + key + "' in [settings] " + reason);
  }
  const toml::node* get(const std::string& key) const { return table_.get(key); }

  void integer(const std::string& key, int& out) const {
    if (const toml::node* n = get(key)) {
      const auto v = n->value<std::int64_t>();
      if (!n->is_integer() || !v) fail(key, "must be an integer");
      if (*v < -2147483647 || *v > 2147483647) fail(key, "is out of range");
      out = static_cast<int>(*v);
    }
  }
  void number(const std::string& key, double& out) const {
    if (const toml::node* n = get(key)) {
      if (!n->is_number()) fail(key, "must be a number");
      out = *n->value<double>();
      if (!std::isfinite(out)) fail(key, "must be finite");
    }
  }
  void boolean(const std::string& key, bool& out) const {
    if (const toml::node* n = get(key)) {
      if (!n->is_boolean()) fail(key, "must be true or false");
      out = *n->value<bool>();
    }
  }
  void string(const std::string& key, std::string& out) const {
    if (const toml::node* n = get(key)) {
      if (!n->is_string()) fail(key, "must be a string");
      out = *n->value<std::string>();
    }
  }
  void color(const std::string& key, Vec3f& out) const {
    if (const toml::node* n = get(key)) {
      const toml::array* a = n->as_array();
      if (!a || a->size() != 3) fail(key, "must be an array of 3 numbers");
      for (std::size_t i = 0; i < 3; ++i) {
        const toml::node& e = *a->get(i);
        if (!e.is_number()) fail(key, "must be an array of 3 numbers");
        const double v = *e.value<double>();
        if (!std::isfinite(v) || v < 0 || !detail::fits_real(v))
          fail(key, "must hold finite non-negative numbers");
        (i == 0 ? out.x : (i == 1 ? out.y : out.z)) = static_cast<float>(v);
      }
    }
  }

 private:
  const toml::table& table_;
  std::string file_;
};

// The first failing range check as a reason, or empty.
std::string range_problem(const RenderSettings& s, std::string& key) {
  auto check = [&](bool ok, const char* k, const char* reason) {
    if (!ok && key.empty()) key = k;
    return ok ? std::string() : std::string(reason);
  };
  std::string r;
  for (const std::string& p :
       {check(s.width >= 1, "width", "must be >= 1"),
        check(s.height >= 1, "height", "must be >= 1"),
        check(s.width <= 65536 && s.height <= 65536, "width", "must be <= 65536"),
        check(s.spp >= 1, "spp", "must be >= 1"),
        check(s.shadow_samples >= 1, "shadow_samples", "must be >= 1"),
        check(s.bounces >= 0 && s.bounces <= 1000, "bounces", "must be in [0, 1000]"),
        check(s.glossy_samples >= 1, "glossy_samples", "must be >= 1"),
        // Continuation random numbers use 2 pairs per (branch, depth) below the shadow pairs
        // at 2^24 (trace_kernel.hpp); keep them apart.
        check(static_cast<double>(s.glossy_samples) * (s.bounces + 1) <= 4.0e6, "glossy_samples",
              "times (bounces + 1) must be <= 4000000"),
        check(s.edge_thickness >= 0, "edge_thickness", "must be >= 0"),
        check(s.crease_angle_deg > 0 && s.crease_angle_deg <= 180, "crease_angle",
              "must be in (0, 180]"),
        check(s.depth_threshold > 0, "depth_threshold", "must be > 0"),
        check(s.stencil_samples >= 1, "stencil_samples", "must be >= 1"),
        check(s.sphere_subdivisions >= 0 && s.sphere_subdivisions <= 8, "sphere_subdivisions",
              "must be in [0, 8]"),
        check(s.camera.fov_deg > 0 && s.camera.fov_deg < 180, "fov", "must be in (0, 180)"),
        check(s.camera.aperture >= 0, "aperture", "must be >= 0"),
        check(s.camera.focus_distance >= 0, "focus_distance", "must be >= 0"),
        check(s.camera.shutter_close >= s.camera.shutter_open, "shutter", "close must be >= open"),
        check(s.style == "none" || s.style == "sketch" || s.style == "color_pencil", "style",
              "must be sketch, color_pencil or none"),
        check(s.chunk_pixels >= 0, "chunk_pixels", "must be >= 0 (0 = auto)"),
        check(s.displacement == "parallax" || s.displacement == "tessellate" ||
                  s.displacement == "off",
              "displacement", "must be parallax, tessellate or off"),
        check(s.displacement_level >= 0 && s.displacement_level <= 10, "displacement_level",
              "must be in [0, 10]"),
        check(s.texture_filter == "cone" || s.texture_filter == "none", "texture_filter",
              "must be cone or none")}) {
    if (r.empty() && !p.empty()) r = p;
  }
  for (const std::string& a : s.aov) {
    if (std::find(std::begin(kAovNames), std::end(kAovNames), a) == std::end(kAovNames) &&
        r.empty()) {
      key = "aov";
      r = "names an unknown AOV '" + a + "' (depth, normal, object, cost, edge)";
    }
  }
  return r;
}

}  // namespace

bool RenderSettings::wants_aov(const std::string& name) const {
  return std::find(aov.begin(), aov.end(), name) != aov.end();
}

void apply_scene_settings(const SceneDescription& scene, RenderSettings& s) {
  check_known_keys(scene.settings->table,
                   {"width",
                    "height",
                    "spp",
                    "soft_shadows",
                    "shadow_samples",
                    "bounces",
                    "glossy_samples",
                    "indirect",
                    "edge_thickness",
                    "crease_angle",
                    "depth_threshold",
                    "stencil_samples",
                    "sphere_subdivisions",
                    "smooth",
                    "background",
                    "seed",
                    "bvh",
                    "aov",
                    "style",
                    "chunk_pixels",
                    "displacement",
                    "displacement_level",
                    "texture_filter"},
                   scene.path, "[settings]");
  const SettingsReader r(scene.settings->table, scene.path);
  r.integer("width", s.width);
  r.integer("height", s.height);
  r.integer("spp", s.spp);
  r.boolean("soft_shadows", s.soft_shadows);
  r.integer("shadow_samples", s.shadow_samples);
  r.integer("bounces", s.bounces);
  r.integer("glossy_samples", s.glossy_samples);
  r.boolean("indirect", s.indirect);
  r.number("edge_thickness", s.edge_thickness);
  r.number("crease_angle", s.crease_angle_deg);
  r.number("depth_threshold", s.depth_threshold);
  r.integer("stencil_samples", s.stencil_samples);
  r.integer("sphere_subdivisions", s.sphere_subdivisions);
  r.boolean("smooth", s.smooth);
  r.integer("chunk_pixels", s.chunk_pixels);
  r.string("displacement", s.displacement);
  r.integer("displacement_level", s.displacement_level);
  r.string("texture_filter", s.texture_filter);
  r.color("background", s.background);
  if (const toml::node* n = r.get("seed")) {
    if (!n->is_integer() || *n->value<std::int64_t>() < 0)
      r.fail("seed", "must be a non-negative integer");
    s.seed = static_cast<std::uint64_t>(*n->value<std::int64_t>());
  }
  std::string bvh = bvh::to_string(s.bvh);
  r.string("bvh", bvh);
  if (!bvh::parse_build_quality(bvh, s.bvh)) r.fail("bvh", "must be \"lbvh\", \"ploc\" or \"sah\"");
  if (const toml::node* n = r.get("aov")) {
    const toml::array* a = n->as_array();
    if (!a) r.fail("aov", "must be an array of strings");
    s.aov.clear();
    for (const toml::node& e : *a) {
      if (!e.is_string()) r.fail("aov", "must be an array of strings");
      s.aov.push_back(*e.value<std::string>());
    }
  }
  r.string("style", s.style);
  std::replace(s.style.begin(), s.style.end(), '-', '_');
  s.ambient = scene.ambient;
  if (scene.has_camera) {
    s.camera = scene.camera;
    s.has_camera = true;
  }
  std::string key;
  const std::string problem = range_problem(s, key);
  if (!problem.empty()) {
    const toml::node* n = r.get(key);
    if (!n && scene.has_camera) {
      throw InputError(scene.path, 0, "[camera] " + key + " " + problem);
    }
    r.fail(key, problem);
  }
}

void validate_settings(const RenderSettings& s, const std::string& where) {
  std::string key;
  const std::string problem = range_problem(s, key);
  if (!problem.empty()) throw InputError(where + ": " + key + " " + problem);
}

}  // namespace rtmini::sketch
