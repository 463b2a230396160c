// TOML scenes as `bake ao` reads them (load_ao_scene: instances, [settings] blockers,
// spheres). Seeds name their meshes "m.obj", a triangle written here.
#include "ao_scene.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  static const std::string mesh = write_scratch("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  (void)mesh;
  const std::string path = write_scratch("x.toml", as_view(data, size));
  expect_input_error_only([&] { (void)rtmini::ao::load_ao_scene(path); });
  return 0;
}
