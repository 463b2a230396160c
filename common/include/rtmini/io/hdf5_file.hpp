#pragma once
// A small RAII wrapper over the HDF5 C API for the timings writer and checkpoints.
// Paths are absolute inside the file ("/chunks/rank"); missing parent groups are
// created. Element types: double, float, std::int64_t, std::uint8_t. Without
// RTMINI_HAVE_HDF5 every operation throws IoError("... built without HDF5").
//
// A file made by create(path) is written to "path.tmp.<pid>" and renamed into place
// by commit(), which first appends a trailer with the XXH64 of every byte (see open());
// destroying it uncommitted deletes the temporary, so readers never see a half-written file. With
// RTMINI_HAVE_PARALLEL_HDF5, create(path, comm) opens it through MPI-IO: every call is then
// collective over comm and commit() renames on rank 0 and synchronises.
//
// Every dataset carries a checksum that read() verifies (InputError when it does not match
// or is missing): an XXH64 attribute for datasets written whole; for datasets written as
// slabs (possibly by several ranks), a companion dataset "<path>.xxh64_slabs" of
// (offset, count, XXH64) rows, one per slab, written by commit().
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#ifdef RTMINI_HAVE_MPI
#include <mpi.h>
#endif

namespace rtmini {

// Turns off libhdf5's own error-stack printing for the whole process (idempotent): every
// HDF5 failure becomes one exception and one line. app_main calls it first thing; Hdf5File
// calls it too, for programs outside app_main.
void quiet_hdf5_errors();

class Hdf5File {
 public:
  static Hdf5File create(const std::string& path);
#ifdef RTMINI_HAVE_MPI
  static Hdf5File create(const std::string& path, MPI_Comm comm);
#endif
  // Read-only. A missing or non-HDF5 file is an InputError "path: reason", and so is any
  // file whose whole-file checksum trailer (appended by commit()) is missing or does not
  // match: libhdf5 never parses a corrupt file.
  static Hdf5File open(const std::string& path);

  Hdf5File(Hdf5File&& other) noexcept;
  Hdf5File& operator=(Hdf5File&& other) noexcept;
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;
  ~Hdf5File();

  // Closes the file and moves it to its final path (created files only).
  void commit();

  void create_group(const std::string& path);
  bool exists(const std::string& path) const;

  // 1D dataset of data.size() elements, or 2D rows x cols (row-major data).
  template <class T>
  void write(const std::string& path, const std::vector<T>& data);
  template <class T>
  void write(const std::string& path, const std::vector<T>& data, std::size_t rows,
             std::size_t cols);
  // All elements, row-major; dims (if given) receives the dataset's shape.
  template <class T>
  std::vector<T> read(const std::string& path, std::vector<std::size_t>* dims = nullptr) const;

  // Collective-friendly 1D output: create the full dataset, then each rank writes
  // its slice [offset, offset + local.size()).
  template <class T>
  void create_dataset(const std::string& path, std::size_t total);
  template <class T>
  void write_slab(const std::string& path, std::size_t offset, const std::vector<T>& local);

  // A list of strings as a 1D fixed-length string dataset.
  void write_strings(const std::string& path, const std::vector<std::string>& values);
  std::vector<std::string> read_strings(const std::string& path) const;

  // Attributes on a group or dataset ("/" = the root).
  void set_attribute(const std::string& object, const std::string& name, const std::string& value);
  void set_attribute(const std::string& object, const std::string& name, const char* value) {
    set_attribute(object, name, std::string(value));
  }
  void set_attribute(const std::string& object, const std::string& name, double value);
  void set_attribute(const std::string& object, const std::string& name, std::int64_t value);
  std::string string_attribute(const std::string& object, const std::string& name) const;
  double double_attribute(const std::string& object, const std::string& name) const;
  std::int64_t int_attribute(const std::string& object, const std::string& name) const;

  const std::string& path() const { return path_; }

 private:
  Hdf5File() = default;
  void close() noexcept;

  std::string path_;      // final path
  std::string tmp_path_;  // where a created file is written until commit()
  std::int64_t id_ = -1;  // hid_t
  bool parallel_ = false;
  int rank_ = 0;
  // This rank's slabs per dataset, (offset, count, XXH64), until commit() writes them.
  std::map<std::string, std::vector<std::array<std::int64_t, 3>>> slabs_;
  void write_slab_checksums();
#ifdef RTMINI_HAVE_MPI
  MPI_Comm comm_ = MPI_COMM_NULL;
#endif
};

}  // namespace rtmini
