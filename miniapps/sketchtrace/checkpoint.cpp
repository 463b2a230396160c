#include "checkpoint.hpp"

#include <cstring>

#include "rtmini/io/error.hpp"
#include "rtmini/io/hdf5_file.hpp"

namespace rtmini::sketch {

void write_checkpoint(const std::string& path, const Checkpoint& c) {
  Hdf5File f = Hdf5File::create(path);
  f.set_attribute("/", "app", "sketchtrace");
  f.set_attribute("/", "signature", c.signature);
  f.set_attribute("/", "inputs", c.inputs);
  f.set_attribute("/", "width", static_cast<std::int64_t>(c.width));
  f.set_attribute("/", "height", static_cast<std::int64_t>(c.height));
  f.set_attribute("/", "pixel_bytes", static_cast<std::int64_t>(sizeof(PixelResult)));
  f.write("/pixels/done", c.done);
  std::vector<std::uint8_t> bytes(c.pixels.size() * sizeof(PixelResult));
  if (!bytes.empty()) std::memcpy(bytes.data(), c.pixels.data(), bytes.size());
  f.write("/pixels/raw", bytes);
  f.commit();
}

Checkpoint read_checkpoint(const std::string& path) {
  Hdf5File f = Hdf5File::open(path);
  Checkpoint c;
  try {
    if (f.string_attribute("/", "app") != "sketchtrace")
      throw InputError(path + ": not a sketchtrace checkpoint");
    if (f.int_attribute("/", "pixel_bytes") != static_cast<std::int64_t>(sizeof(PixelResult)))
      throw InputError(path + ": checkpoint from an incompatible build");
    c.signature = f.string_attribute("/", "signature");
    c.inputs = f.string_attribute("/", "inputs");
    c.width = static_cast<int>(f.int_attribute("/", "width"));
    c.height = static_cast<int>(f.int_attribute("/", "height"));
    c.done = f.read<std::uint8_t>("/pixels/done");
    const std::vector<std::uint8_t> bytes = f.read<std::uint8_t>("/pixels/raw");
    if (c.done.size() != static_cast<std::size_t>(c.width) * c.height ||
        bytes.size() != static_cast<std::size_t>(c.width) * c.height * sizeof(PixelResult))
      throw InputError(path + ": checkpoint datasets have the wrong size");
    c.pixels.resize(bytes.size() / sizeof(PixelResult));
    if (!bytes.empty()) std::memcpy(c.pixels.data(), bytes.data(), bytes.size());
  } catch (const IoError& e) {
    throw InputError(path + ": not a readable sketchtrace checkpoint (" + e.what() + ")");
  }
  return c;
}

}  // namespace rtmini::sketch
