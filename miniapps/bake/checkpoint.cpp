#include "checkpoint.hpp"

#include "rtmini/io/error.hpp"
#include "rtmini/io/hdf5_file.hpp"

namespace rtmini::bake {

void write_checkpoint(const std::string& path, const Checkpoint& cp) {
  Hdf5File f = Hdf5File::create(path);
  std::vector<float> flat(cp.colors.size() * 3);
  for (std::size_t i = 0; i < cp.colors.size(); ++i) {
    flat[3 * i] = cp.colors[i].x;
    flat[3 * i + 1] = cp.colors[i].y;
    flat[3 * i + 2] = cp.colors[i].z;
  }
  f.write("/colors", flat, cp.colors.size(), 3);
  f.set_attribute("/", "app", "bake");
  f.set_attribute("/", "iteration", static_cast<std::int64_t>(cp.iteration));
  f.set_attribute("/", "parameter_hash", cp.parameter_hash);
  f.set_attribute("/", "inputs", cp.inputs);
  f.set_attribute("/", "vertices", cp.vertices);
  f.set_attribute("/", "viewpoints", static_cast<std::int64_t>(cp.viewpoints));
  f.commit();
}

Checkpoint read_checkpoint(const std::string& path, const std::string& expected_hash,
                           const std::vector<InputFileHash>& inputs, std::int64_t expected_colors) {
  Hdf5File f = Hdf5File::open(path);
  if (!f.exists("/colors")) throw InputError(path, 0, "not a bake checkpoint (no /colors)");
  Checkpoint cp;
  cp.inputs = f.string_attribute("/", "inputs");
  verify_input_hashes(path, cp.inputs, inputs);
  cp.parameter_hash = f.string_attribute("/", "parameter_hash");
  if (cp.parameter_hash != expected_hash)
    throw InputError(path, 0,
                     "checkpoint was written for different parameters or another scene "
                     "(parameter hash " +
                         cp.parameter_hash + ", this run " + expected_hash + ")");
  cp.iteration = static_cast<int>(f.int_attribute("/", "iteration"));
  cp.vertices = f.int_attribute("/", "vertices");
  cp.viewpoints = static_cast<int>(f.int_attribute("/", "viewpoints"));
  std::vector<std::size_t> dims;
  const std::vector<float> flat = f.read<float>("/colors", &dims);
  if (dims.size() != 2 || dims[1] != 3 || static_cast<std::int64_t>(dims[0]) != expected_colors)
    throw InputError(path, 0, "checkpoint colour map has the wrong size");
  cp.colors.resize(dims[0]);
  for (std::size_t i = 0; i < dims[0]; ++i)
    cp.colors[i] = Vec3f(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return cp;
}

}  // namespace rtmini::bake
