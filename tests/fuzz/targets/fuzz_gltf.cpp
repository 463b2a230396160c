// glTF 2.0 (read_gltf through read_mesh, and gltf_files). Input: a .glb when it starts with
// the GLB magic "glTF", else the text of a .gltf (buffers as data: URIs; an external URI names
// a file of the scratch folder, which does not exist).
#include "fuzz_input.hpp"
#include "rtmini/io/gltf_reader.hpp"
#include "rtmini/io/obj_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const std::string_view bytes = as_view(data, size);
  const bool binary = bytes.substr(0, 4) == "glTF";
  const std::string path = write_scratch(binary ? "x.glb" : "x.gltf", bytes);
  expect_input_error_only([&] { (void)rtmini::read_mesh(path); });
  expect_input_error_only([&] { (void)rtmini::gltf_files(path); });
  return 0;
}
