// sketchtrace --cost-map: the HDF5 cost-map reader (read_cost_map_file). The key it must
// match is taken from the file itself, so mutations get past the "other parameters" check.
#include "cost_map_file.hpp"
#include "fuzz_input.hpp"
#include "rtmini/io/hdf5_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rtmini::fuzz;
  const std::string path = write_scratch("x.h5", as_view(data, size));
  expect_input_error_only([&] {
    rtmini::sketch::CostMapKey key;
    {
      const rtmini::Hdf5File f = rtmini::Hdf5File::open(path);
      key.signature = f.string_attribute("/", "signature");
      key.width = static_cast<int>(f.int_attribute("/", "width"));
      key.height = static_cast<int>(f.int_attribute("/", "height"));
      key.stride = static_cast<int>(f.int_attribute("/", "stride"));
    }
    // The grid the app would expect for this key (any count is fine: it is only compared).
    const std::int64_t s = key.stride > 0 ? key.stride : 1;
    const std::size_t cells =
        static_cast<std::size_t>(((key.width + s - 1) / s) * ((key.height + s - 1) / s));
    std::vector<float> cost;
    (void)rtmini::sketch::read_cost_map_file(path, key, cells, cost);
  });
  return 0;
}
