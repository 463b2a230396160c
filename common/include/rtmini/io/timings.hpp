#pragma once
// Per-rank timings file (--timings FILE.h5), written by rank 0 from gathered data.
// All times are seconds since the run's start; R = ranks, P = phases, I = iterations
// (may be 0), C = chunks (pixel chunks or vertex batches).
//
//   /                     attributes: app, version, git_hash, backend, strategy, scene,
//                         parameters (JSON string), created_utc (ISO 8601), ranks, threads (int64)
//   /phases/names         [P] fixed-length strings
//   /phases/start, /end   [R x P] float64
//   /chunks/rank, /iteration, /work_units, /rays   [C] int64
//   /chunks/start, /end   [C] float64
//   /ranks/completion_time, /idle_time             [R] float64
//   /ranks/messages_sent, /bytes_sent, /rays, /work_units   [R] int64
//   /iterations/trace_time, /allgather_time, /write_time   [R x I] float64
//   /iterations/allgather_bytes                     [R x I] int64
#include <cstdint>
#include <string>
#include <vector>

namespace rtmini {

struct TimingsData {
  std::string app, version, git_hash, backend, strategy, scene;
  std::string parameters;   // JSON text
  std::string created_utc;  // filled with the current UTC time when empty
  int ranks = 1;
  int threads = 1;

  std::vector<std::string> phase_names;
  std::vector<double> phase_start, phase_end;  // ranks x phases, row-major

  std::vector<std::int64_t> chunk_rank, chunk_iteration, chunk_work_units, chunk_rays;
  std::vector<double> chunk_start, chunk_end;

  std::vector<double> rank_completion_time, rank_idle_time;
  std::vector<std::int64_t> rank_messages_sent, rank_bytes_sent, rank_rays, rank_work_units;

  int iterations = 0;
  std::vector<double> iteration_trace_time, iteration_allgather_time, iteration_write_time;
  std::vector<std::int64_t> iteration_allgather_bytes;  // ranks x iterations
};

// Validates the vector sizes against ranks/phases/iterations (std::invalid_argument on
// a mismatch: a caller bug) and writes the file atomically. IoError on I/O failure.
void write_timings(const std::string& path, const TimingsData& data);

// Reads a file written by write_timings (tests, tools).
TimingsData read_timings(const std::string& path);

}  // namespace rtmini
