// sketchtrace --restart: the HDF5 checkpoint reader (sketch::read_checkpoint).
#include "fuzz_input.hpp"
#include "sketchtrace/checkpoint.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const std::string path = write_scratch("x.h5", as_view(data, size));
  expect_input_error_only([&] { (void)rtmini::sketch::read_checkpoint(path); });
  return 0;
}
