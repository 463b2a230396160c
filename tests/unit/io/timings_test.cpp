#include "rtmini/io/timings.hpp"

#include <gtest/gtest.h>

#define XXH_INLINE_ALL  // header-only use: the test reseals a file as Hdf5File::commit does
#include <xxhash.h>

#include "../optional_features.hpp"
#include "io_test_util.hpp"
#include "rtmini/io/error.hpp"
#include "rtmini/io/hdf5_file.hpp"

namespace rtmini {
namespace {

TimingsData make_timings(int ranks, int iterations) {
  TimingsData d;
  d.app = "bake";
  d.version = "0.1.0";
  d.git_hash = "abc123";
  d.backend = "OpenMP";
  d.strategy = "static";
  d.scene = "cube.bs";
  d.parameters = R"({"viewpoints":100})";
  d.ranks = ranks;
  d.threads = 2;
  d.phase_names = {"read", "bvh", "trace"};
  for (int r = 0; r < ranks; ++r)
    for (int p = 0; p < 3; ++p) {
      d.phase_start.push_back(r + 0.1 * p);
      d.phase_end.push_back(r + 0.1 * p + 0.05);
    }
  for (int c = 0; c < 5; ++c) {
    d.chunk_rank.push_back(c % ranks);
    d.chunk_iteration.push_back(c / 2);
    d.chunk_start.push_back(c * 0.5);
    d.chunk_end.push_back(c * 0.5 + 0.25);
    d.chunk_work_units.push_back(100 + c);
    d.chunk_rays.push_back(1000000000000LL + c);
  }
  for (int r = 0; r < ranks; ++r) {
    d.rank_completion_time.push_back(10.0 + r);
    d.rank_idle_time.push_back(0.5 * r);
    d.rank_messages_sent.push_back(r * 3);
    d.rank_bytes_sent.push_back(r * 4096);
    d.rank_rays.push_back(r * 77);
    d.rank_work_units.push_back(r * 11);
  }
  d.iterations = iterations;
  for (int i = 0; i < ranks * iterations; ++i) {
    d.iteration_trace_time.push_back(1.0 + i);
    d.iteration_allgather_time.push_back(0.01 * i);
    d.iteration_allgather_bytes.push_back(8 * i);
    d.iteration_write_time.push_back(0.2 * i);
  }
  return d;
}

void expect_equal(const TimingsData& a, const TimingsData& b) {
  EXPECT_EQ(a.app, b.app);
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.git_hash, b.git_hash);
  EXPECT_EQ(a.backend, b.backend);
  EXPECT_EQ(a.strategy, b.strategy);
  EXPECT_EQ(a.scene, b.scene);
  EXPECT_EQ(a.parameters, b.parameters);
  EXPECT_EQ(a.ranks, b.ranks);
  EXPECT_EQ(a.threads, b.threads);
  EXPECT_EQ(a.phase_names, b.phase_names);
  EXPECT_EQ(a.phase_start, b.phase_start);
  EXPECT_EQ(a.phase_end, b.phase_end);
  EXPECT_EQ(a.chunk_rank, b.chunk_rank);
  EXPECT_EQ(a.chunk_iteration, b.chunk_iteration);
  EXPECT_EQ(a.chunk_start, b.chunk_start);
  EXPECT_EQ(a.chunk_end, b.chunk_end);
  EXPECT_EQ(a.chunk_work_units, b.chunk_work_units);
  EXPECT_EQ(a.chunk_rays, b.chunk_rays);
  EXPECT_EQ(a.rank_completion_time, b.rank_completion_time);
  EXPECT_EQ(a.rank_idle_time, b.rank_idle_time);
  EXPECT_EQ(a.rank_messages_sent, b.rank_messages_sent);
  EXPECT_EQ(a.rank_bytes_sent, b.rank_bytes_sent);
  EXPECT_EQ(a.rank_rays, b.rank_rays);
  EXPECT_EQ(a.rank_work_units, b.rank_work_units);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.iteration_trace_time, b.iteration_trace_time);
  EXPECT_EQ(a.iteration_allgather_time, b.iteration_allgather_time);
  EXPECT_EQ(a.iteration_allgather_bytes, b.iteration_allgather_bytes);
  EXPECT_EQ(a.iteration_write_time, b.iteration_write_time);
}

TEST(Timings, RoundTrip) {
  RTMINI_REQUIRE_HDF5();
  test::TempDir dir;
  const TimingsData d = make_timings(3, 4);
  write_timings(dir.file("t.h5"), d);
  EXPECT_EQ(test::count_files(dir.path()), 1);
  const TimingsData back = read_timings(dir.file("t.h5"));
  expect_equal(d, back);
  EXPECT_EQ(back.created_utc.size(), 20u);  // filled in: YYYY-MM-DDTHH:MM:SSZ
}

TEST(Timings, ZeroIterations) {
  RTMINI_REQUIRE_HDF5();
  test::TempDir dir;
  const TimingsData d = make_timings(2, 0);
  write_timings(dir.file("t.h5"), d);
  const TimingsData back = read_timings(dir.file("t.h5"));
  expect_equal(d, back);
  const Hdf5File f = Hdf5File::open(dir.file("t.h5"));
  std::vector<std::size_t> dims;
  f.read<double>("/iterations/trace_time", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{2, 0}));
  f.read<double>("/phases/start", &dims);
  EXPECT_EQ(dims, (std::vector<std::size_t>{2, 3}));
}

TEST(Timings, SizeMismatchIsRejectedWithoutAFile) {
  RTMINI_REQUIRE_HDF5();
  test::TempDir dir;
  TimingsData d = make_timings(2, 1);
  d.rank_rays.pop_back();
  EXPECT_THROW(write_timings(dir.file("t.h5"), d), std::invalid_argument);
  EXPECT_EQ(test::count_files(dir.path()), 0);
}

TEST(Hdf5File, TypesSlabsAttributesAndUncommittedCleanup) {
  RTMINI_REQUIRE_HDF5();
  test::TempDir dir;
  {
    Hdf5File f = Hdf5File::create(dir.file("c.h5"));
    f.write<float>("/a/f", {1.5f, -2.f});
    f.write<std::uint8_t>("/a/u8", {0, 255, 7, 9, 1, 2}, 2, 3);
    f.create_dataset<std::int64_t>("/slab", 5);
    f.write_slab<std::int64_t>("/slab", 2, {20, 30, 40});
    f.write_slab<std::int64_t>("/slab", 0, {0, 10});
    f.set_attribute("/a", "note", "hello");
    f.set_attribute("/a/f", "scale", 0.25);
    f.set_attribute("/", "count", std::int64_t{42});
    f.create_group("/empty/group");
    f.commit();
  }
  const Hdf5File f = Hdf5File::open(dir.file("c.h5"));
  EXPECT_EQ(f.read<float>("/a/f"), (std::vector<float>{1.5f, -2.f}));
  std::vector<std::size_t> dims;
  EXPECT_EQ(f.read<std::uint8_t>("/a/u8", &dims), (std::vector<std::uint8_t>{0, 255, 7, 9, 1, 2}));
  EXPECT_EQ(dims, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(f.read<std::int64_t>("/slab"), (std::vector<std::int64_t>{0, 10, 20, 30, 40}));
  EXPECT_EQ(f.string_attribute("/a", "note"), "hello");
  EXPECT_EQ(f.double_attribute("/a/f", "scale"), 0.25);
  EXPECT_EQ(f.int_attribute("/", "count"), 42);
  EXPECT_TRUE(f.exists("/empty/group"));
  EXPECT_FALSE(f.exists("/missing/deeper"));
  // A file being read that lacks what rtmini wrote is bad input (exit 2), not an I/O failure.
  EXPECT_THROW(f.read<double>("/missing"), InputError);

  { Hdf5File abandoned = Hdf5File::create(dir.file("never.h5")); }
  EXPECT_EQ(test::count_files(dir.path()), 1);  // only c.h5
  EXPECT_THROW(Hdf5File::open(dir.file("never.h5")), InputError);
}

// Slab-written datasets carry per-slab checksums (issue 17): a changed byte in any slab is
// refused on read, as a changed byte of a dataset written whole is.
TEST(Hdf5File, SlabChecksumsRefuseAChangedByte) {
  RTMINI_REQUIRE_HDF5();
  test::TempDir dir;
  const std::int64_t marker = 0x0123456789abcdefLL;
  {
    Hdf5File f = Hdf5File::create(dir.file("s.h5"));
    f.create_dataset<std::int64_t>("/slab", 4);
    f.write_slab<std::int64_t>("/slab", 2, {marker, 7});
    f.write_slab<std::int64_t>("/slab", 0, {1, 2});
    f.commit();
  }
  EXPECT_EQ(Hdf5File::open(dir.file("s.h5")).read<std::int64_t>("/slab"),
            (std::vector<std::int64_t>{1, 2, marker, 7}));
  std::string bytes = test::read_file(dir.file("s.h5"));
  const std::string needle(reinterpret_cast<const char*>(&marker), sizeof marker);
  const std::size_t at = bytes.find(needle);
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(bytes.find(needle, at + 1), std::string::npos);  // the data, not the checksum table
  bytes[at] ^= 0x01;
  // As it is, the whole-file trailer (Hdf5File::commit) refuses the file before libhdf5 reads
  // it; resealed, the slab's own checksum must still refuse it.
  test::write_file(dir.file("unsealed.h5"), bytes);
  EXPECT_THROW(Hdf5File::open(dir.file("unsealed.h5")), InputError);
  const std::size_t body = bytes.size() - 16;  // the trailer: 8 magic bytes, XXH64 (LE)
  const std::uint64_t seal = XXH64(bytes.data(), body, 0);
  for (int i = 0; i < 8; ++i) bytes[body + 8 + i] = static_cast<char>((seal >> (8 * i)) & 0xff);
  test::write_file(dir.file("bad.h5"), bytes);
  try {
    Hdf5File::open(dir.file("bad.h5")).read<std::int64_t>("/slab");
    FAIL() << "a changed byte in a slab was not refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("checksum mismatch in '/slab' (slab at 2)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rtmini
