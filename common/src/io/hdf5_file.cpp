#include "rtmini/io/hdf5_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"

#ifdef RTMINI_HAVE_HDF5
#include <hdf5.h>
#define XXH_INLINE_ALL
#include <xxhash.h>
#endif

namespace rtmini {

#ifdef RTMINI_HAVE_HDF5
namespace {

template <class T>
hid_t native_type();
template <>
hid_t native_type<double>() {
  return H5T_NATIVE_DOUBLE;
}
template <>
hid_t native_type<float>() {
  return H5T_NATIVE_FLOAT;
}
template <>
hid_t native_type<std::int64_t>() {
  return H5T_NATIVE_INT64;
}
template <>
hid_t native_type<std::uint8_t>() {
  return H5T_NATIVE_UINT8;
}

// Closes an HDF5 handle of any kind at scope exit: H5Idec_ref closes files, datasets,
// dataspaces, types and property lists alike, so one class serves them all.
class Handle {
 public:
  explicit Handle(hid_t id) : id_(id) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  ~Handle() {
    if (id_ >= 0) H5Idec_ref(id_);
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_;
};

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw IoError(file + ": HDF5 " + what);
}

// A file being read that does not hold what rtmini wrote is bad input (exit 2).
[[noreturn]] void corrupt(const std::string& file, const std::string& what) {
  throw InputError(file, 0, "corrupt or foreign HDF5 file: " + what);
}

// Sanity limits checked before any allocation driven by a file's metadata.
constexpr std::uint64_t kMaxDatasetBytes = std::uint64_t(1) << 36;  // 64 GiB
constexpr std::size_t kMaxAttributeChars = std::size_t(1) << 20;
// The attribute holding a dataset's checksum (XXH64 of its bytes, seed 0).
constexpr const char* kChecksumAttribute = "xxh64";
// The companion dataset of a slab-written dataset: (offset, count, XXH64) rows.
constexpr const char* kSlabTableSuffix = ".xxh64_slabs";

std::int64_t checksum_of(const void* data, std::size_t bytes) {
  return static_cast<std::int64_t>(XXH64(data, bytes, 0));
}

// Every file rtmini commits ends in a trailer: kTrailerMagic, then the XXH64 (seed 0,
// little endian) of every byte before it. libhdf5 does not look past the end address its
// superblock records, so the file stays a plain HDF5 file (h5py, h5dump read it). open()
// checks the trailer before libhdf5 parses a byte: libhdf5 1.10 is not safe on corrupt
// metadata (fuzzing found a heap over-read while decoding attribute messages and error paths
// that leave the library unable to close), so a corrupt file must never reach it.
constexpr char kTrailerMagic[8] = {'r', 't', 'm', 'i', 'n', 'i', 'h', '5'};
constexpr std::size_t kTrailerBytes = sizeof(kTrailerMagic) + 8;

// XXH64 of the first `bytes` bytes of `f`, read from the start; false on a short read.
bool hash_prefix(std::FILE* f, std::uint64_t bytes, std::uint64_t& hash) {
  XXH64_state_t state;
  XXH64_reset(&state, 0);
  std::vector<char> buffer(static_cast<std::size_t>(std::min<std::uint64_t>(bytes, 1 << 20)));
  for (std::uint64_t left = bytes; left > 0;) {
    const std::size_t want = static_cast<std::size_t>(std::min<std::uint64_t>(left, buffer.size()));
    if (std::fread(buffer.data(), 1, want, f) != want) return false;
    XXH64_update(&state, buffer.data(), want);
    left -= want;
  }
  hash = XXH64_digest(&state);
  return true;
}

void encode_le64(std::uint64_t v, unsigned char* out) {
  for (int i = 0; i < 8; ++i) out[i] = static_cast<unsigned char>(v >> (8 * i));
}

// Appends the trailer to the closed file `tmp`; IoError when it cannot.
void append_trailer(const std::string& tmp, const std::string& final_path) {
  std::FILE* f = std::fopen(tmp.c_str(), "r+b");
  if (f == nullptr) throw IoError(final_path + ": cannot reopen the HDF5 file to seal it");
  std::uint64_t hash = 0;
  bool ok = std::fseek(f, 0, SEEK_END) == 0;
  const long size = ok ? std::ftell(f) : -1;
  ok = size >= 0 && std::fseek(f, 0, SEEK_SET) == 0 &&
       hash_prefix(f, static_cast<std::uint64_t>(size), hash);
  unsigned char trailer[kTrailerBytes];
  std::memcpy(trailer, kTrailerMagic, sizeof(kTrailerMagic));
  encode_le64(hash, trailer + sizeof(kTrailerMagic));
  ok = ok && std::fseek(f, 0, SEEK_END) == 0 &&
       std::fwrite(trailer, 1, kTrailerBytes, f) == kTrailerBytes;
  // fclose flushes: its failure (disk full) is a write failure too.
  if (std::fclose(f) != 0 || !ok)
    throw IoError(final_path + ": cannot seal the HDF5 file (write failed)");
}

// InputError unless `path` ends in a trailer matching its content.
void verify_trailer(const std::string& path) {
  // (Opening a fifo would block until someone writes to it.)
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw InputError(path, 0, "not a regular file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw InputError(path, 0, "cannot open as an HDF5 file");
  std::uint64_t hash = 0;
  unsigned char trailer[kTrailerBytes];
  const bool seeked = std::fseek(f, 0, SEEK_END) == 0;
  const long size = seeked ? std::ftell(f) : -1;
  bool ok = size >= static_cast<long>(kTrailerBytes) && std::fseek(f, 0, SEEK_SET) == 0 &&
            hash_prefix(f, static_cast<std::uint64_t>(size) - kTrailerBytes, hash) &&
            std::fread(trailer, 1, kTrailerBytes, f) == kTrailerBytes;
  std::fclose(f);
  if (!ok || std::memcmp(trailer, kTrailerMagic, sizeof(kTrailerMagic)) != 0)
    corrupt(path, "no rtmini trailer (truncated, or not written by rtmini)");
  unsigned char expected[8];
  encode_le64(hash, expected);
  if (std::memcmp(trailer + sizeof(kTrailerMagic), expected, 8) != 0)
    corrupt(path, "whole-file checksum mismatch");
}

hid_t check(hid_t id, const std::string& file, const std::string& what) {
  if (id < 0) fail(file, what);
  return id;
}

// Intermediate groups are created on the fly: datasets are named by path ("/phases/start")
// and no writer has to create "/phases" first.
hid_t link_create_plist() {
  const hid_t plist = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(plist, 1);
  return plist;
}

// Collective transfers for a parallel file: every rank takes part in every write, so MPI-IO can
// merge the ranks' pieces into few large requests (independent writes to a parallel filesystem
// are much slower). The price: a rank with nothing to write must still call (write_slab).
hid_t transfer_plist(bool parallel) {
  const hid_t plist = H5Pcreate(H5P_DATASET_XFER);
#ifdef RTMINI_HAVE_PARALLEL_HDF5
  if (parallel) H5Pset_dxpl_mpio(plist, H5FD_MPIO_COLLECTIVE);
#else
  (void)parallel;
#endif
  return plist;
}

}  // namespace

Hdf5File Hdf5File::create(const std::string& path) {
  quiet_hdf5_errors();
  Hdf5File f;
  f.path_ = path;
  check_replaceable(path);
  remove_stale_temporaries(path);
  f.tmp_path_ = path + ".tmp." + std::to_string(::getpid());
  f.id_ = H5Fcreate(f.tmp_path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  if (f.id_ < 0) throw IoError(path + ": cannot create HDF5 file");
  return f;
}

#ifdef RTMINI_HAVE_MPI
Hdf5File Hdf5File::create(const std::string& path, MPI_Comm comm) {
#ifdef RTMINI_HAVE_PARALLEL_HDF5
  quiet_hdf5_errors();
  Hdf5File f;
  f.path_ = path;
  f.parallel_ = true;
  f.comm_ = comm;
  MPI_Comm_rank(comm, &f.rank_);
  // Every rank must agree on the temporary name: take rank 0's pid.
  long pid = static_cast<long>(::getpid());
  MPI_Bcast(&pid, 1, MPI_LONG, 0, comm);
  f.tmp_path_ = path + ".tmp." + std::to_string(pid);
  const Handle fapl(H5Pcreate(H5P_FILE_ACCESS));
  H5Pset_fapl_mpio(fapl.get(), comm, MPI_INFO_NULL);
  f.id_ = H5Fcreate(f.tmp_path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (f.id_ < 0) throw IoError(path + ": cannot create HDF5 file (parallel)");
  return f;
#else
  (void)comm;
  throw IoError(path + ": built without parallel HDF5");
#endif
}
#endif

Hdf5File Hdf5File::open(const std::string& path) {
  quiet_hdf5_errors();
  Hdf5File f;
  f.path_ = path;
  verify_trailer(path);
  f.id_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f.id_ < 0) throw InputError(path, 0, "cannot open as an HDF5 file");
  return f;
}

Hdf5File::Hdf5File(Hdf5File&& other) noexcept { *this = std::move(other); }

Hdf5File& Hdf5File::operator=(Hdf5File&& other) noexcept {
  if (this != &other) {
    close();
    path_ = std::move(other.path_);
    tmp_path_ = std::move(other.tmp_path_);
    id_ = other.id_;
    parallel_ = other.parallel_;
    rank_ = other.rank_;
#ifdef RTMINI_HAVE_MPI
    comm_ = other.comm_;
#endif
    other.id_ = -1;
    other.tmp_path_.clear();
  }
  return *this;
}

Hdf5File::~Hdf5File() { close(); }

void Hdf5File::close() noexcept {
  if (id_ >= 0) H5Fclose(id_);
  id_ = -1;
  // An uncommitted created file is incomplete: remove it.
  if (!tmp_path_.empty() && rank_ == 0) std::remove(tmp_path_.c_str());
  tmp_path_.clear();
}

void Hdf5File::commit() {
  if (tmp_path_.empty()) return;
  write_slab_checksums();
  // No size to compare with (HDF5's own idea of the file size differs from the
  // closed file's): the write errors H5Fclose reports, sealing it with the trailer
  // (append_trailer reads every byte back) and the fsync are the checks.
  const bool closed = H5Fclose(id_) >= 0;
  id_ = -1;
  int status = 0;
  std::string problem = "cannot close HDF5 file";
  if (rank_ == 0) {
    if (!closed) {
      std::remove(tmp_path_.c_str());
      status = 1;
    } else {
      try {
        append_trailer(tmp_path_, path_);
        commit_temporary(tmp_path_, path_, -1);
      } catch (const IoError& e) {
        std::remove(tmp_path_.c_str());  // (commit_temporary removes it itself; harmless)
        problem = e.what();
        status = 1;
      }
    }
  }
#ifdef RTMINI_HAVE_MPI
  if (parallel_) MPI_Bcast(&status, 1, MPI_INT, 0, comm_);
#endif
  tmp_path_.clear();
  if (status != 0) throw IoError(problem.rfind(path_, 0) == 0 ? problem : path_ + ": " + problem);
}

void Hdf5File::create_group(const std::string& path) {
  const Handle lcpl(link_create_plist());
  const Handle group(H5Gcreate2(id_, path.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!group.valid()) fail(path_, "cannot create group '" + path + "'");
}

bool Hdf5File::exists(const std::string& path) const {
  if (path == "/") return true;
  // Check each prefix: H5Lexists fails on a missing intermediate group.
  for (std::size_t pos = 1; pos <= path.size(); ++pos) {
    if (pos != path.size() && path[pos] != '/') continue;
    if (H5Lexists(id_, path.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return true;
}

namespace {

template <class T>
void write_dataset(hid_t file, const std::string& file_path, bool parallel, const std::string& path,
                   const std::vector<T>& data, int rank, const hsize_t* dims) {
  const Handle space(check(H5Screate_simple(rank, dims, nullptr), file_path, "dataspace"));
  const Handle lcpl(link_create_plist());
  const Handle dset(H5Dcreate2(file, path.c_str(), native_type<T>(), space.get(), lcpl.get(),
                               H5P_DEFAULT, H5P_DEFAULT));
  if (!dset.valid()) fail(file_path, "cannot create dataset '" + path + "'");
  // The checksum goes in before the data: an empty dataset still carries one, and a reader
  // meets a mismatch, never a dataset that silently lacks its checksum.
  const std::int64_t sum = checksum_of(data.data(), data.size() * sizeof(T));
  const Handle scalar(H5Screate(H5S_SCALAR));
  const Handle attr(H5Acreate2(dset.get(), kChecksumAttribute, H5T_NATIVE_INT64, scalar.get(),
                               H5P_DEFAULT, H5P_DEFAULT));
  if (!attr.valid() || H5Awrite(attr.get(), H5T_NATIVE_INT64, &sum) < 0)
    fail(file_path, "cannot write the checksum of '" + path + "'");
  if (data.empty()) return;
  const Handle xfer(transfer_plist(parallel));
  if (H5Dwrite(dset.get(), native_type<T>(), H5S_ALL, H5S_ALL, xfer.get(), data.data()) < 0)
    fail(file_path, "cannot write dataset '" + path + "'");
}

// The element count of dataset `dset` of T, validated against the file before
// anything is allocated: simple extent of rank 1..8 without overflow, the
// element type T's class and size, a sane total, and (contiguous storage as
// written here) exactly that many bytes stored.
template <class T>
std::size_t checked_count(hid_t dset, const std::string& file, const std::string& path,
                          std::vector<std::size_t>* dims) {
  const Handle space(H5Dget_space(dset));
  const int rank = space.valid() ? H5Sget_simple_extent_ndims(space.get()) : -1;
  if (rank < 1 || rank > 8) corrupt(file, "bad dataspace of '" + path + "'");
  hsize_t shape[8];
  if (H5Sget_simple_extent_dims(space.get(), shape, nullptr) != rank)
    corrupt(file, "bad dataspace of '" + path + "'");
  std::uint64_t count = 1;
  if (dims) dims->clear();
  for (int i = 0; i < rank; ++i) {
    if (shape[i] != 0 && count > kMaxDatasetBytes / shape[i])
      corrupt(file, "'" + path + "' is implausibly large");
    count *= shape[i];
    if (dims) dims->push_back(static_cast<std::size_t>(shape[i]));
  }
  if (count * sizeof(T) > kMaxDatasetBytes) corrupt(file, "'" + path + "' is implausibly large");
  const Handle type(H5Dget_type(dset));
  const H5T_class_t want = H5Tget_class(native_type<T>());
  if (!type.valid() || H5Tget_class(type.get()) != want || H5Tget_size(type.get()) != sizeof(T))
    corrupt(file, "'" + path + "' has another element type");
  if (count > 0 && H5Dget_storage_size(dset) != count * sizeof(T))
    corrupt(file, "'" + path + "' stores " + std::to_string(H5Dget_storage_size(dset)) +
                      " bytes, its shape says " + std::to_string(count * sizeof(T)));
  return static_cast<std::size_t>(count);
}

// Datasets written whole carry a checksum: it must match what was read.
// (Datasets assembled from slabs by several ranks have none.)
// The slab table of `path` ("<path>.xxh64_slabs"): rows (offset, count, XXH64) that must
// tile the dataset's `elements` exactly and match its bytes.
void verify_slab_checksums(hid_t file, const std::string& file_path, const std::string& path,
                           const void* data, std::size_t elements, std::size_t element_bytes);

void verify_checksum(hid_t file, hid_t dset, const std::string& file_path, const std::string& path,
                     const void* data, std::size_t elements, std::size_t element_bytes) {
  if (H5Aexists(dset, kChecksumAttribute) > 0) {
    const Handle attr(H5Aopen(dset, kChecksumAttribute, H5P_DEFAULT));
    std::int64_t stored = 0;
    if (!attr.valid() || H5Aread(attr.get(), H5T_NATIVE_INT64, &stored) < 0 ||
        stored != checksum_of(data, elements * element_bytes))
      corrupt(file_path, "checksum mismatch in '" + path + "'");
    return;
  }
  verify_slab_checksums(file, file_path, path, data, elements, element_bytes);
}

void verify_slab_checksums(hid_t file, const std::string& file_path, const std::string& path,
                           const void* data, std::size_t elements, std::size_t element_bytes) {
  const std::string table_path = path + kSlabTableSuffix;
  if (H5Lexists(file, table_path.c_str(), H5P_DEFAULT) <= 0)
    corrupt(file_path, "no checksum for '" + path + "'");
  const Handle table(H5Dopen2(file, table_path.c_str(), H5P_DEFAULT));
  if (!table.valid()) corrupt(file_path, "no dataset '" + table_path + "'");
  std::vector<std::size_t> dims;
  std::vector<std::int64_t> rows(
      checked_count<std::int64_t>(table.get(), file_path, table_path, &dims));
  if (dims.size() != 2 || dims[1] != 3)
    corrupt(file_path, "'" + table_path + "' is not a table of (offset, count, checksum)");
  if (!rows.empty() &&
      H5Dread(table.get(), H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows.data()) < 0)
    corrupt(file_path, "cannot read dataset '" + table_path + "'");
  verify_checksum(file, table.get(), file_path, table_path, rows.data(), rows.size(),
                  sizeof(std::int64_t));
  // The slabs, in file order, must tile [0, elements) and each match its checksum.
  std::vector<std::array<std::int64_t, 3>> slabs(rows.size() / 3);
  for (std::size_t i = 0; i < slabs.size(); ++i)
    slabs[i] = {rows[3 * i], rows[3 * i + 1], rows[3 * i + 2]};
  std::sort(slabs.begin(), slabs.end());
  std::int64_t next = 0;
  const char* bytes = static_cast<const char*>(data);
  for (const auto& [offset, count, hash] : slabs) {
    if (offset != next || count <= 0 || static_cast<std::size_t>(offset + count) > elements)
      corrupt(file_path, "slab table of '" + path + "' does not cover the dataset");
    if (checksum_of(bytes + static_cast<std::size_t>(offset) * element_bytes,
                    static_cast<std::size_t>(count) * element_bytes) != hash)
      corrupt(file_path,
              "checksum mismatch in '" + path + "' (slab at " + std::to_string(offset) + ")");
    next = offset + count;
  }
  if (static_cast<std::size_t>(next) != elements)
    corrupt(file_path, "slab table of '" + path + "' does not cover the dataset");
}

}  // namespace

void quiet_hdf5_errors() {
  static std::once_flag once;
  std::call_once(once, [] { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); });
}

template <class T>
void Hdf5File::write(const std::string& path, const std::vector<T>& data) {
  const hsize_t dims[1] = {data.size()};
  write_dataset(id_, path_, parallel_, path, data, 1, dims);
}

template <class T>
void Hdf5File::write(const std::string& path, const std::vector<T>& data, std::size_t rows,
                     std::size_t cols) {
  if (data.size() != rows * cols)
    fail(path_, "dataset '" + path + "' size does not match its shape");
  const hsize_t dims[2] = {rows, cols};
  write_dataset(id_, path_, parallel_, path, data, 2, dims);
}

template <class T>
std::vector<T> Hdf5File::read(const std::string& path, std::vector<std::size_t>* dims) const {
  const Handle dset(H5Dopen2(id_, path.c_str(), H5P_DEFAULT));
  if (!dset.valid()) corrupt(path_, "no dataset '" + path + "'");
  std::vector<T> data(checked_count<T>(dset.get(), path_, path, dims));
  if (!data.empty() &&
      H5Dread(dset.get(), native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    corrupt(path_, "cannot read dataset '" + path + "'");
  verify_checksum(id_, dset.get(), path_, path, data.data(), data.size(), sizeof(T));
  return data;
}

template <class T>
void Hdf5File::create_dataset(const std::string& path, std::size_t total) {
  const hsize_t dims[1] = {total};
  const Handle space(check(H5Screate_simple(1, dims, nullptr), path_, "dataspace"));
  const Handle lcpl(link_create_plist());
  const Handle dset(H5Dcreate2(id_, path.c_str(), native_type<T>(), space.get(), lcpl.get(),
                               H5P_DEFAULT, H5P_DEFAULT));
  if (!dset.valid()) fail(path_, "cannot create dataset '" + path + "'");
}

template <class T>
void Hdf5File::write_slab(const std::string& path, std::size_t offset,
                          const std::vector<T>& local) {
  const Handle dset(H5Dopen2(id_, path.c_str(), H5P_DEFAULT));
  if (!dset.valid()) fail(path_, "no dataset '" + path + "'");
  const Handle file_space(H5Dget_space(dset.get()));
  const hsize_t start[1] = {offset};
  const hsize_t count[1] = {local.size()};
  const Handle mem_space(H5Screate_simple(1, count, nullptr));
  // A rank with nothing to write still joins the collective call with an empty selection.
  if (local.empty()) {
    H5Sselect_none(file_space.get());
    H5Sselect_none(mem_space.get());
  } else if (H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr) <
             0) {
    fail(path_, "slab out of range in '" + path + "'");
  }
  const Handle xfer(transfer_plist(parallel_));
  if (H5Dwrite(dset.get(), native_type<T>(), mem_space.get(), file_space.get(), xfer.get(),
               local.data()) < 0)
    fail(path_, "cannot write slab of '" + path + "'");
  if (!local.empty())
    slabs_[path].push_back({static_cast<std::int64_t>(offset),
                            static_cast<std::int64_t>(local.size()),
                            checksum_of(local.data(), local.size() * sizeof(T))});
}

// Every rank's slab rows of each slab-written dataset, gathered (collective in a parallel
// file: every rank writes the same table), as "<path>.xxh64_slabs".
void Hdf5File::write_slab_checksums() {
  for (auto& [path, rows] : slabs_) {
    std::vector<std::int64_t> flat;
    for (const auto& r : rows) flat.insert(flat.end(), r.begin(), r.end());
#ifdef RTMINI_HAVE_MPI
    if (parallel_) {
      int size = 0, mine = static_cast<int>(flat.size());
      MPI_Comm_size(comm_, &size);
      std::vector<int> counts(static_cast<std::size_t>(size)), displs(counts.size(), 0);
      MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
      for (std::size_t r = 1; r < counts.size(); ++r) displs[r] = displs[r - 1] + counts[r - 1];
      std::vector<std::int64_t> all(static_cast<std::size_t>(displs.back() + counts.back()));
      MPI_Allgatherv(flat.data(), mine, MPI_INT64_T, all.data(), counts.data(), displs.data(),
                     MPI_INT64_T, comm_);
      flat = std::move(all);
    }
#endif
    write(path + kSlabTableSuffix, flat, flat.size() / 3, 3);
  }
  slabs_.clear();
}

// Fixed-width, NUL-padded strings (width of the longest, at least 1), for the same reason as
// set_attribute: variable-length strings are heap pointers in the file, unsafe to read when
// the file is corrupt. h5py and the analysis package read either kind the same way.
void Hdf5File::write_strings(const std::string& path, const std::vector<std::string>& values) {
  std::size_t width = 1;
  for (const std::string& s : values) width = std::max(width, s.size());
  std::vector<char> buffer(values.size() * width, '\0');
  for (std::size_t i = 0; i < values.size(); ++i)
    std::memcpy(buffer.data() + i * width, values[i].data(), values[i].size());
  const Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), width);
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  const hsize_t dims[1] = {values.size()};
  const Handle space(H5Screate_simple(1, dims, nullptr));
  const Handle lcpl(link_create_plist());
  const Handle dset(
      H5Dcreate2(id_, path.c_str(), type.get(), space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT));
  if (!dset.valid()) fail(path_, "cannot create dataset '" + path + "'");
  if (values.empty()) return;
  const Handle xfer(transfer_plist(parallel_));
  if (H5Dwrite(dset.get(), type.get(), H5S_ALL, H5S_ALL, xfer.get(), buffer.data()) < 0)
    fail(path_, "cannot write dataset '" + path + "'");
}

std::vector<std::string> Hdf5File::read_strings(const std::string& path) const {
  const Handle dset(H5Dopen2(id_, path.c_str(), H5P_DEFAULT));
  if (!dset.valid()) corrupt(path_, "no dataset '" + path + "'");
  const Handle type(H5Dget_type(dset.get()));
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
    corrupt(path_, "'" + path + "' is not a fixed-length string dataset");
  const std::size_t width = H5Tget_size(type.get());
  const Handle space(H5Dget_space(dset.get()));
  const hssize_t count = H5Sget_simple_extent_npoints(space.get());
  if (width == 0 || width > kMaxAttributeChars || count < 0 ||
      static_cast<std::uint64_t>(count) > kMaxDatasetBytes / width)
    corrupt(path_, "'" + path + "' is implausibly large");
  std::vector<char> buffer(static_cast<std::size_t>(count) * width);
  if (count > 0 &&
      H5Dread(dset.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, buffer.data()) < 0)
    fail(path_, "cannot read dataset '" + path + "'");
  std::vector<std::string> values;
  for (hssize_t i = 0; i < count; ++i) {
    const char* s = buffer.data() + i * width;
    values.emplace_back(s, strnlen(s, width));
  }
  return values;
}

namespace {

// Replaces attribute `name` on `object` with a scalar of `type` (deleted first: HDF5 cannot
// change an existing attribute's type or size, and a restarted run rewrites its attributes).
void put_attribute(hid_t file, const std::string& file_path, const std::string& object,
                   const std::string& name, hid_t type, const void* value) {
  const Handle obj(H5Oopen(file, object.c_str(), H5P_DEFAULT));
  if (!obj.valid()) fail(file_path, "no object '" + object + "' for attribute '" + name + "'");
  if (H5Aexists(obj.get(), name.c_str()) > 0) H5Adelete(obj.get(), name.c_str());
  const Handle space(H5Screate(H5S_SCALAR));
  const hid_t attr =
      H5Acreate2(obj.get(), name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT);
  if (attr < 0) fail(file_path, "cannot create attribute '" + name + "'");
  const herr_t status = H5Awrite(attr, type, value);
  H5Aclose(attr);
  if (status < 0) fail(file_path, "cannot write attribute '" + name + "'");
}

hid_t open_attribute(hid_t file, const std::string& file_path, const std::string& object,
                     const std::string& name) {
  const hid_t attr = H5Aopen_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT);
  if (attr < 0) corrupt(file_path, "no attribute '" + name + "' on '" + object + "'");
  return attr;
}

template <class T>
T read_scalar_attribute(hid_t file, const std::string& file_path, const std::string& object,
                        const std::string& name) {
  const hid_t attr = open_attribute(file, file_path, object, name);
  T value{};
  const Handle type(H5Aget_type(attr));
  const Handle space(H5Aget_space(attr));
  const bool scalar = type.valid() && space.valid() &&
                      H5Tget_class(type.get()) == H5Tget_class(native_type<T>()) &&
                      H5Sget_simple_extent_npoints(space.get()) == 1;
  const herr_t status = scalar ? H5Aread(attr, native_type<T>(), &value) : -1;
  H5Aclose(attr);
  if (status < 0) corrupt(file_path, "cannot read attribute '" + name + "'");
  return value;
}

}  // namespace

void Hdf5File::set_attribute(const std::string& object, const std::string& name,
                             const std::string& value) {
  // Fixed-length UTF-8: libhdf5 reads variable-length strings through heap
  // pointers stored in the file, which a corrupt file turns into a crash.
  const Handle type(H5Tcopy(H5T_C_S1));
  H5Tset_size(type.get(), std::max<std::size_t>(1, value.size()));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  std::vector<char> bytes(std::max<std::size_t>(1, value.size()), '\0');
  std::memcpy(bytes.data(), value.data(), value.size());
  put_attribute(id_, path_, object, name, type.get(), bytes.data());
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name, double value) {
  put_attribute(id_, path_, object, name, H5T_NATIVE_DOUBLE, &value);
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name,
                             std::int64_t value) {
  put_attribute(id_, path_, object, name, H5T_NATIVE_INT64, &value);
}

std::string Hdf5File::string_attribute(const std::string& object, const std::string& name) const {
  const Handle attr(open_attribute(id_, path_, object, name));
  const Handle type(H5Aget_type(attr.get()));
  const Handle space(H5Aget_space(attr.get()));
  // Only fixed-length strings are read (see set_attribute); the size comes
  // from the file, so it is bounded before the buffer is allocated.
  const bool fixed = type.valid() && H5Tget_class(type.get()) == H5T_STRING &&
                     H5Tis_variable_str(type.get()) == 0 && space.valid() &&
                     H5Sget_simple_extent_npoints(space.get()) == 1;
  const std::size_t width = fixed ? H5Tget_size(type.get()) : 0;
  if (width == 0 || width > kMaxAttributeChars)
    corrupt(path_, "attribute '" + name + "' is not a fixed-length string");
  std::vector<char> bytes(width, '\0');
  const Handle mem(H5Tcopy(type.get()));
  if (H5Aread(attr.get(), mem.get(), bytes.data()) < 0)
    corrupt(path_, "attribute '" + name + "' is not a readable string");
  return std::string(bytes.data(), strnlen(bytes.data(), width));
}

double Hdf5File::double_attribute(const std::string& object, const std::string& name) const {
  return read_scalar_attribute<double>(id_, path_, object, name);
}

std::int64_t Hdf5File::int_attribute(const std::string& object, const std::string& name) const {
  return read_scalar_attribute<std::int64_t>(id_, path_, object, name);
}

#else  // without HDF5: every entry point reports the missing feature.

namespace {
[[noreturn]] void no_hdf5(const std::string& path) {
  throw IoError(path + ": built without HDF5 (configure with RTMINI_ENABLE_HDF5=ON)");
}
}  // namespace

Hdf5File Hdf5File::create(const std::string& path) { no_hdf5(path); }
#ifdef RTMINI_HAVE_MPI
Hdf5File Hdf5File::create(const std::string& path, MPI_Comm) { no_hdf5(path); }
#endif
Hdf5File Hdf5File::open(const std::string& path) { no_hdf5(path); }
Hdf5File::Hdf5File(Hdf5File&& other) noexcept : path_(std::move(other.path_)) {}
Hdf5File& Hdf5File::operator=(Hdf5File&&) noexcept { return *this; }
Hdf5File::~Hdf5File() = default;
void Hdf5File::close() noexcept {}
void quiet_hdf5_errors() {}
void Hdf5File::write_slab_checksums() {}
void Hdf5File::commit() { no_hdf5(path_); }
void Hdf5File::create_group(const std::string&) { no_hdf5(path_); }
bool Hdf5File::exists(const std::string&) const { no_hdf5(path_); }
template <class T>
void Hdf5File::write(const std::string&, const std::vector<T>&) {
  no_hdf5(path_);
}
template <class T>
void Hdf5File::write(const std::string&, const std::vector<T>&, std::size_t, std::size_t) {
  no_hdf5(path_);
}
template <class T>
std::vector<T> Hdf5File::read(const std::string&, std::vector<std::size_t>*) const {
  no_hdf5(path_);
}
template <class T>
void Hdf5File::create_dataset(const std::string&, std::size_t) {
  no_hdf5(path_);
}
template <class T>
void Hdf5File::write_slab(const std::string&, std::size_t, const std::vector<T>&) {
  no_hdf5(path_);
}
void Hdf5File::write_strings(const std::string&, const std::vector<std::string>&) {
  no_hdf5(path_);
}
std::vector<std::string> Hdf5File::read_strings(const std::string&) const { no_hdf5(path_); }
void Hdf5File::set_attribute(const std::string&, const std::string&, const std::string&) {
  no_hdf5(path_);
}
void Hdf5File::set_attribute(const std::string&, const std::string&, double) { no_hdf5(path_); }
void Hdf5File::set_attribute(const std::string&, const std::string&, std::int64_t) {
  no_hdf5(path_);
}
std::string Hdf5File::string_attribute(const std::string&, const std::string&) const {
  no_hdf5(path_);
}
double Hdf5File::double_attribute(const std::string&, const std::string&) const { no_hdf5(path_); }
std::int64_t Hdf5File::int_attribute(const std::string&, const std::string&) const {
  no_hdf5(path_);
}

#endif

#define RTMINI_HDF5_INSTANTIATE(T)                                                                \
  template void Hdf5File::write<T>(const std::string&, const std::vector<T>&);                    \
  template void Hdf5File::write<T>(const std::string&, const std::vector<T>&, std::size_t,        \
                                   std::size_t);                                                  \
  template std::vector<T> Hdf5File::read<T>(const std::string&, std::vector<std::size_t>*) const; \
  template void Hdf5File::create_dataset<T>(const std::string&, std::size_t);                     \
  template void Hdf5File::write_slab<T>(const std::string&, std::size_t, const std::vector<T>&);

RTMINI_HDF5_INSTANTIATE(double)
RTMINI_HDF5_INSTANTIATE(float)
RTMINI_HDF5_INSTANTIATE(std::int64_t)
RTMINI_HDF5_INSTANTIATE(std::uint8_t)
#undef RTMINI_HDF5_INSTANTIATE

}  // namespace rtmini
