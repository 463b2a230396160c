// The text bakeshop format (.bs, read_bakeshop).
#include "fuzz_input.hpp"
#include "rtmini/io/bakeshop.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const std::string path = write_scratch("x.bs", as_view(data, size));
  expect_input_error_only([&] { (void)rtmini::read_bakeshop(path); });
  return 0;
}
