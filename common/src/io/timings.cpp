#include "rtmini/io/timings.hpp"

#include <ctime>
#include <stdexcept>

#include "rtmini/io/hdf5_file.hpp"

namespace rtmini {
namespace {

// ISO 8601 in UTC: runs on machines in different time zones sort and compare by this text.
std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

template <class T>
void expect_size(const std::vector<T>& v, std::size_t n, const char* name) {
  if (v.size() != n)
    throw std::invalid_argument(std::string("timings: ") + name + " has " +
                                std::to_string(v.size()) + " entries, expected " +
                                std::to_string(n));
}

// Every array's length against the counts it is declared with, before anything is written: a
// mismatch is a bug in the caller (hence invalid_argument, not an I/O error), and the analysis
// package reshapes by these counts, so a wrong length would be misread silently.
void validate(const TimingsData& d) {
  const std::size_t r = static_cast<std::size_t>(d.ranks);
  const std::size_t p = d.phase_names.size();
  const std::size_t i = static_cast<std::size_t>(d.iterations);
  const std::size_t c = d.chunk_rank.size();
  if (d.ranks < 1 || d.iterations < 0) throw std::invalid_argument("timings: bad ranks/iterations");
  expect_size(d.phase_start, r * p, "phase_start");
  expect_size(d.phase_end, r * p, "phase_end");
  expect_size(d.chunk_iteration, c, "chunk_iteration");
  expect_size(d.chunk_start, c, "chunk_start");
  expect_size(d.chunk_end, c, "chunk_end");
  expect_size(d.chunk_work_units, c, "chunk_work_units");
  expect_size(d.chunk_rays, c, "chunk_rays");
  expect_size(d.rank_completion_time, r, "rank_completion_time");
  expect_size(d.rank_idle_time, r, "rank_idle_time");
  expect_size(d.rank_messages_sent, r, "rank_messages_sent");
  expect_size(d.rank_bytes_sent, r, "rank_bytes_sent");
  expect_size(d.rank_rays, r, "rank_rays");
  expect_size(d.rank_work_units, r, "rank_work_units");
  expect_size(d.iteration_trace_time, r * i, "iteration_trace_time");
  expect_size(d.iteration_allgather_time, r * i, "iteration_allgather_time");
  expect_size(d.iteration_allgather_bytes, r * i, "iteration_allgather_bytes");
  expect_size(d.iteration_write_time, r * i, "iteration_write_time");
}

}  // namespace

void write_timings(const std::string& path, const TimingsData& d) {
  validate(d);
  const std::size_t r = static_cast<std::size_t>(d.ranks);
  const std::size_t p = d.phase_names.size();
  const std::size_t i = static_cast<std::size_t>(d.iterations);
  Hdf5File f = Hdf5File::create(path);
  f.set_attribute("/", "app", d.app);
  f.set_attribute("/", "version", d.version);
  f.set_attribute("/", "git_hash", d.git_hash);
  f.set_attribute("/", "backend", d.backend);
  f.set_attribute("/", "strategy", d.strategy);
  f.set_attribute("/", "scene", d.scene);
  f.set_attribute("/", "parameters", d.parameters);
  f.set_attribute("/", "created_utc", d.created_utc.empty() ? utc_now() : d.created_utc);
  f.set_attribute("/", "ranks", static_cast<std::int64_t>(d.ranks));
  f.set_attribute("/", "threads", static_cast<std::int64_t>(d.threads));

  f.write_strings("/phases/names", d.phase_names);
  f.write("/phases/start", d.phase_start, r, p);
  f.write("/phases/end", d.phase_end, r, p);

  f.write("/chunks/rank", d.chunk_rank);
  f.write("/chunks/iteration", d.chunk_iteration);
  f.write("/chunks/start", d.chunk_start);
  f.write("/chunks/end", d.chunk_end);
  f.write("/chunks/work_units", d.chunk_work_units);
  f.write("/chunks/rays", d.chunk_rays);

  f.write("/ranks/completion_time", d.rank_completion_time);
  f.write("/ranks/idle_time", d.rank_idle_time);
  f.write("/ranks/messages_sent", d.rank_messages_sent);
  f.write("/ranks/bytes_sent", d.rank_bytes_sent);
  f.write("/ranks/rays", d.rank_rays);
  f.write("/ranks/work_units", d.rank_work_units);

  f.write("/iterations/trace_time", d.iteration_trace_time, r, i);
  f.write("/iterations/allgather_time", d.iteration_allgather_time, r, i);
  f.write("/iterations/allgather_bytes", d.iteration_allgather_bytes, r, i);
  f.write("/iterations/write_time", d.iteration_write_time, r, i);
  // The file becomes visible only now (temporary + rename): a job that dies mid-write leaves
  // the old timings or none, never a file the analysis would half-read.
  f.commit();
}

TimingsData read_timings(const std::string& path) {
  const Hdf5File f = Hdf5File::open(path);
  TimingsData d;
  d.app = f.string_attribute("/", "app");
  d.version = f.string_attribute("/", "version");
  d.git_hash = f.string_attribute("/", "git_hash");
  d.backend = f.string_attribute("/", "backend");
  d.strategy = f.string_attribute("/", "strategy");
  d.scene = f.string_attribute("/", "scene");
  d.parameters = f.string_attribute("/", "parameters");
  d.created_utc = f.string_attribute("/", "created_utc");
  d.ranks = static_cast<int>(f.int_attribute("/", "ranks"));
  d.threads = static_cast<int>(f.int_attribute("/", "threads"));

  d.phase_names = f.read_strings("/phases/names");
  d.phase_start = f.read<double>("/phases/start");
  d.phase_end = f.read<double>("/phases/end");

  d.chunk_rank = f.read<std::int64_t>("/chunks/rank");
  d.chunk_iteration = f.read<std::int64_t>("/chunks/iteration");
  d.chunk_start = f.read<double>("/chunks/start");
  d.chunk_end = f.read<double>("/chunks/end");
  d.chunk_work_units = f.read<std::int64_t>("/chunks/work_units");
  d.chunk_rays = f.read<std::int64_t>("/chunks/rays");

  d.rank_completion_time = f.read<double>("/ranks/completion_time");
  d.rank_idle_time = f.read<double>("/ranks/idle_time");
  d.rank_messages_sent = f.read<std::int64_t>("/ranks/messages_sent");
  d.rank_bytes_sent = f.read<std::int64_t>("/ranks/bytes_sent");
  d.rank_rays = f.read<std::int64_t>("/ranks/rays");
  d.rank_work_units = f.read<std::int64_t>("/ranks/work_units");

  // The iteration count is not stored as an attribute: the [ranks x iterations] shape says it.
  std::vector<std::size_t> dims;
  d.iteration_trace_time = f.read<double>("/iterations/trace_time", &dims);
  d.iterations = dims.size() == 2 ? static_cast<int>(dims[1]) : 0;
  d.iteration_allgather_time = f.read<double>("/iterations/allgather_time");
  d.iteration_allgather_bytes = f.read<std::int64_t>("/iterations/allgather_bytes");
  d.iteration_write_time = f.read<double>("/iterations/write_time");
  return d;
}

}  // namespace rtmini
