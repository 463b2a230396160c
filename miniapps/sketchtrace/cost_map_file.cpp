#include "cost_map_file.hpp"

#include <cstdint>
#include <fstream>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/hdf5_file.hpp"

namespace rtmini::sketch {

bool read_cost_map_file(const std::string& path, const CostMapKey& key, std::size_t cells,
                        std::vector<float>& cost) {
  if (path.empty()) return false;
  // The file is replaced when it does not match, so it must be replaceable; checked
  // before opening it, which would block forever on a fifo.
  check_replaceable(path);
  if (!std::ifstream(path)) return false;
  Hdf5File f = Hdf5File::open(path);
  if (f.string_attribute("/", "app") != "sketchtrace-cost-map" ||
      f.string_attribute("/", "signature") != key.signature ||
      f.int_attribute("/", "width") != key.width || f.int_attribute("/", "height") != key.height ||
      f.int_attribute("/", "stride") != key.stride)
    return false;
  std::vector<float> values = f.read<float>("/cost");
  if (values.size() != cells) throw InputError(path, 0, "cost map has the wrong size");
  cost = std::move(values);
  return true;
}

void write_cost_map_file(const std::string& path, const CostMapKey& key,
                         const std::vector<float>& cost) {
  Hdf5File f = Hdf5File::create(path);
  f.set_attribute("/", "app", "sketchtrace-cost-map");
  f.set_attribute("/", "signature", key.signature);
  f.set_attribute("/", "width", static_cast<std::int64_t>(key.width));
  f.set_attribute("/", "height", static_cast<std::int64_t>(key.height));
  f.set_attribute("/", "stride", static_cast<std::int64_t>(key.stride));
  f.write("/cost", cost);
  f.commit();
}

}  // namespace rtmini::sketch
