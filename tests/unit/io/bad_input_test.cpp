// Every malformed file under tests/data/bad must fail with an InputError whose
// message is "<file>:<line>: <reason>" at the offending line.
#include <gtest/gtest.h>

#include <functional>

#include "rtmini/io/error.hpp"
#include "rtmini/io/image.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/scene_file.hpp"

namespace rtmini {
namespace {

struct BadInput {
  const char* file;
  long line;
  const char* reason;              // a substring the message must contain after the prefix
  const char* reported = nullptr;  // the file the message names, when not `file` (an MTL)
};

std::ostream& operator<<(std::ostream& os, const BadInput& b) { return os << b.file; }

class BadInputTest : public ::testing::TestWithParam<BadInput> {};

void load(const std::string& path) {
  const std::string ext = path.substr(path.find_last_of('.'));
  if (ext == ".toml") {
    load_scene_meshes(read_scene_file(path));
  } else if (ext == ".ppm") {
    read_image(path);
  } else {
    read_mesh(path);
  }
}

TEST_P(BadInputTest, ReportsFileLineAndReason) {
  const BadInput& bad = GetParam();
  const std::string path = std::string(RTMINI_TEST_BAD_DIR) + "/" + bad.file;
  try {
    load(path);
    FAIL() << path << " was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    const std::string named =
        bad.reported ? std::string(RTMINI_TEST_BAD_DIR) + "/" + bad.reported : path;
    const std::string prefix = named + ":" + std::to_string(bad.line) + ": ";
    EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
    EXPECT_NE(message.find(bad.reason, prefix.size()), std::string::npos) << message;
  }
}

const BadInput kBadInputs[] = {
    {"obj_nan_vertex.obj", 3, "non-finite value 'nan'"},
    {"obj_inf_vertex.obj", 2, "1e999"},
    {"obj_index_out_of_range.obj", 4, "vertex index 9 out of range"},
    {"obj_face_before_vertices.obj", 2, "vertex index 1 out of range (0 defined"},
    {"obj_negative_index.obj", 4, "vertex index -5 out of range"},
    {"obj_zero_index.obj", 4, "index 0 is invalid"},
    {"obj_text_in_number.obj", 2, "invalid number 'abc'"},
    {"obj_wrong_field_count.obj", 2, "vertex needs 3 coordinates"},
    {"obj_face_two_vertices.obj", 3, "face needs at least 3 vertices"},
    {"obj_bad_normal_index.obj", 5, "normal index 2 out of range"},
    {"obj_missing_mtl.obj", 1, "cannot open material library"},
    {"obj_mtl_nan.obj", 4, "non-finite value 'nan' in material statement Ks", "obj_mtl_nan.mtl"},
    {"obj_unknown_material.obj", 6, "material 'blue' is not defined"},
    {"bs_empty.bs", 1, "empty file"},
    {"bs_missing_bang.bs", 6, "missing '!'"},
    {"bs_index_out_of_range.bs", 6, "vertex index 3 out of range [0, 3)"},
    {"bs_negative_index.bs", 6, "vertex index -2 out of range"},
    {"bs_material_out_of_range.bs", 7, "material index 1 out of range [-1, 1)"},
    {"bs_nan.bs", 2, "non-finite value 'NaN'"},
    {"bs_viewpoint_inf.bs", 2, "non-finite value 'inf' in viewpoint"},
    {"bs_wrong_field_count.bs", 2, "vertex needs 3 fields, got 4"},
    {"bs_material_field_count.bs", 3, "needs 9 fields, got 8"},
    {"bs_face_field_count.bs", 6, "got 3 fields"},
    {"bs_text_in_number.bs", 6, "invalid number 'one'"},
    {"bs_trailing_garbage.bs", 8, "unexpected content after the final '!'"},
    {"bs_viewpoint_before_vertex.bs", 1, "viewpoint line before any vertex"},
    {"bs_missing_blank_line.bs", 4, "material line in the vertices section"},
    {"bs_blank_in_faces.bs", 7, "blank line inside the faces section"},
    {"toml_unknown_key.toml", 3, "unknown key 'foo' in [camera]"},
    {"toml_unknown_top_key.toml", 3, "unknown key 'cameras'"},
    {"toml_wrong_type.toml", 2, "'fov_deg' in [camera] must be a number"},
    {"toml_bad_vector.toml", 2, "must be an array of 3 numbers"},
    {"toml_missing_mesh.toml", 3, "cannot be opened"},
    {"toml_syntax_error.toml", 2, "end-of-file"},
    {"toml_unknown_light_type.toml", 2, "\"spot\""},
    {"toml_missing_light_field.toml", 1, "missing required key 'intensity'"},
    {"toml_unknown_material_ref.toml", 7, "names no [[materials]] entry: 'blue'"},
    {"toml_negative_radius.toml", 3, "'radius' in [[spheres]] must be positive"},
    {"bs_material_inf.bs", 5, "non-finite value 'inf' in material"},
    {"toml_nan_number.toml", 3, "'fov_deg' in [camera] must be finite"},
    {"toml_inf_vector.toml", 3, "'center' in [[spheres]] must be finite"},
    {"toml_ao_nan_translate.toml", 4, "'translate' in [[meshes]] must be finite"},
#ifndef RTMINI_USE_DOUBLE
    // Finite in double, infinite once converted to the default single precision.
    {"obj_float_overflow_vertex.obj", 2, "'1e39' in vertex is beyond the single-precision range"},
    {"bs_position_overflow.bs", 3, "'-4e38' in vertex is beyond the single-precision range"},
    {"toml_float_overflow.toml", 4, "'ke' in [[materials]] is beyond the single-precision range"},
#endif
    {"ppm_bad_magic.ppm", 1, "unsupported magic 'P5'"},
    {"ppm_truncated.ppm", 4, "binary raster truncated"},
    {"ppm_sample_over_max.ppm", 5, "sample 16 out of range [0, 15]"},
    // Headers claiming 8000 x 8000 pixels with no raster: refused before allocating.
    {"ppm_header_only_huge.ppm", 3, "binary raster truncated"},
    {"ppm_ascii_huge_truncated.ppm", 3, "ASCII raster truncated"},
};

#ifdef RTMINI_HAVE_PNG
// A valid PNG header claiming 1000000 x 1000000 pixels (found by fuzzing: std::bad_alloc, which
// the apps reported as a resource error) is bad input, refused before anything is allocated.
TEST(BadPng, HugeHeaderIsRefusedBeforeAllocating) {
  const std::string path = std::string(RTMINI_TEST_BAD_DIR) + "/png_huge_header.png";
  try {
    read_image(path);
    FAIL() << path << " was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": image of 1000000 x 1000000 pixels"),
              std::string::npos)
        << e.what();
  }
}
#endif

INSTANTIATE_TEST_SUITE_P(Io, BadInputTest, ::testing::ValuesIn(kBadInputs),
                         // Not named `info`: the macro's own parameter has that name.
                         [](const ::testing::TestParamInfo<BadInput>& test) {
                           std::string name = test.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace rtmini
