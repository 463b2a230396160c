// OBJ and its MTL library (read_obj). Input: the OBJ text, optionally followed by a line
// "#%mtl" and the text of m.mtl (seeds name their library "m.mtl").
#include "fuzz_input.hpp"
#include "rtmini/io/obj_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const auto [obj, mtl] = split_at_marker(as_view(data, size), "mtl");
  write_scratch("m.mtl", mtl);
  const std::string path = write_scratch("x.obj", obj);
  expect_input_error_only([&] { (void)rtmini::read_obj(path); });
  return 0;
}
