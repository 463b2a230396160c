// The binary bakeshop format (.bsb, read_bakeshop_binary).
#include "fuzz_input.hpp"
#include "rtmini/io/bakeshop_binary.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const std::string path = write_scratch("x.bsb", as_view(data, size));
  expect_input_error_only([&] { (void)rtmini::read_bakeshop_binary(path); });
  return 0;
}
