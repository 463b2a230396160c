// PNG reference images (read_png, libpng's simplified API).
#include "fuzz_input.hpp"
#include "rtmini/io/image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const std::string path = write_scratch("x.png", as_view(data, size));
  expect_input_error_only([&] { (void)rtmini::read_png(path); });
  return 0;
}
