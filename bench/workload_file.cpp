#include "workload_file.hpp"

#include <cstdio>
#include <cstring>
#include <vector>

#include "rtmini/io/atomic_file.hpp"
#include "rtmini/io/error.hpp"

namespace rtmini::bench {

namespace {

constexpr char kMagic[8] = {'R', 'T', 'M', 'W', 'O', 'R', 'K', '1'};
constexpr std::int64_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;
constexpr std::uint64_t kRaysPerBlock = 1 << 16;

void put(std::FILE* f, const void* data, std::size_t bytes, const std::string& path) {
  if (bytes > 0 && std::fwrite(data, 1, bytes, f) != bytes)
    throw IoError(path + ": write failed (disk full?)");
}

void put_floats(std::FILE* f, std::vector<float>& block, const std::string& path) {
  put(f, block.data(), block.size() * sizeof(float), path);
  block.clear();
}

}  // namespace

std::int64_t workload_file_bytes(std::uint64_t num_tris, std::uint64_t num_rays) {
  return kHeaderBytes + static_cast<std::int64_t>(num_tris * 9 * sizeof(float) +
                                                  num_rays * (8 * sizeof(float) + sizeof(int)));
}

void write_workload(const std::string& path, const WorkloadView& w) {
  write_file_atomic(
      path,
      [&](const std::string& tmp) {
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) throw IoError(path + ": cannot open for writing");
        try {
          const std::uint32_t flags[2] = {w.any_hit ? 1u : 0u, 0u};
          const std::uint64_t counts[2] = {w.num_tris, w.num_rays};
          put(f, kMagic, sizeof kMagic, path);
          put(f, flags, sizeof flags, path);
          put(f, counts, sizeof counts, path);
          std::vector<float> block;
          for (std::uint64_t t = 0; t < w.num_tris; ++t) {
            for (const Vec3& v : {w.tris[t].a, w.tris[t].b, w.tris[t].c})
              block.insert(block.end(), {float(v.x), float(v.y), float(v.z)});
            if (block.size() >= 9 * kRaysPerBlock) put_floats(f, block, path);
          }
          put_floats(f, block, path);
          for (std::uint64_t i = 0; i < w.num_rays; ++i) {
            const Ray& r = w.rays[i];
            block.insert(block.end(), {float(r.org.x), float(r.org.y), float(r.org.z),
                                       float(r.dir.x), float(r.dir.y), float(r.dir.z),
                                       float(r.tmin), float(r.tmax)});
            if (block.size() >= 8 * kRaysPerBlock) put_floats(f, block, path);
          }
          put_floats(f, block, path);
          static_assert(sizeof(int) == 4, "answers are written as int32");
          put(f, w.answers, w.num_rays * sizeof(int), path);
        } catch (...) {
          std::fclose(f);
          throw;
        }
        if (std::fclose(f) != 0) throw IoError(path + ": write failed on close");
      },
      workload_file_bytes(w.num_tris, w.num_rays));
}

}  // namespace rtmini::bench
