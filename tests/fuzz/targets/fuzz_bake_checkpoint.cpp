// bake --restart: the HDF5 checkpoint reader (bake::read_checkpoint). The expected
// parameter hash and map size are taken from the file itself, so mutations get past the
// "other parameters" check and reach the datasets.
#include "bake/checkpoint.hpp"
#include "fuzz_input.hpp"
#include "rtmini/io/hdf5_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const std::string path = write_scratch("x.h5", as_view(data, size));
  expect_input_error_only([&] {
    std::string hash;
    std::int64_t vertices = 0;
    {
      const rtmini::Hdf5File f = rtmini::Hdf5File::open(path);
      hash = f.string_attribute("/", "parameter_hash");
      vertices = f.int_attribute("/", "vertices");
    }
    (void)rtmini::bake::read_checkpoint(path, hash, {}, vertices);
  });
  return 0;
}
