// TOML scene files as sketchtrace reads them: read_scene_file, the meshes it names
// (load_scene_meshes) and the [settings]/[camera] render parameters (apply_scene_settings,
// validate_settings). Seeds name their meshes "m.obj" or "m.bs", a triangle written here.
#include "fuzz_input.hpp"
#include "render_settings.hpp"
#include "rtmini/io/bakeshop.hpp"
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/scene_file.hpp"

namespace {

// The meshes a seed scene may name, written once per process.
void write_scene_meshes() {
  static const bool done = [] {
    const std::string obj =
        rtmini::fuzz::write_scratch("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    rtmini::write_bakeshop(rtmini::fuzz::scratch_dir() + "/m.bs", rtmini::read_obj(obj));
    return true;
  }();
  (void)done;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  write_scene_meshes();
  const std::string path = write_scratch("x.toml", as_view(data, size));
  expect_input_error_only([&] {
    const rtmini::SceneDescription scene = rtmini::read_scene_file(path);
    (void)rtmini::load_scene_meshes(scene);
    rtmini::sketch::RenderSettings settings;
    rtmini::sketch::apply_scene_settings(scene, settings);
    rtmini::sketch::validate_settings(settings, path);
  });
  return 0;
}
