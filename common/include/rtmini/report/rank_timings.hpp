#pragma once
// The --timings writer every program shares: each rank hands in its own phases (from its
// PhaseTimer), dispatches ("chunks": pixel chunks, vertex batches), optional iterations and
// totals; they are gathered to rank 0, which writes the file (layout in io/timings.hpp).
// Collective: every rank calls it, whether or not it has records.
#include <cstdint>
#include <string>
#include <vector>

#include "rtmini/parallel/communicator.hpp"
#include "rtmini/report/timer.hpp"

namespace rtmini {

struct RankChunk {
  std::int64_t iteration = 0, work_units = 0, rays = 0;
  double start = 0, end = 0;
};

struct RankIteration {
  double trace = 0, allgather = 0, write = 0;
  std::int64_t allgather_bytes = 0;
};

struct RankTimings {
  std::vector<RankChunk> chunks;
  std::vector<RankIteration> iterations;  // the same count on every rank
  double completion = 0, idle = 0;        // seconds since the run start; seconds
  std::int64_t rays = 0, work_units = 0;
};

struct TimingsLabels {
  std::string app, strategy, scene;
  std::string parameters = "{}";  // JSON text
  // The phases to record, in this order; empty: every phase any rank timed, first seen first.
  std::vector<std::string> phases;
};

// The union of every rank's phase names, each rank's first-seen order concatenated by rank,
// each name once: ranks may time different phases (rank 0 alone writes checkpoints), and a
// per-phase reduction or [ranks x phases] array needs the same names on every rank. Collective.
std::vector<std::string> agreed_phase_names(const Communicator& comm, const PhaseTimer& timer);

void write_rank_timings(const std::string& path, const Communicator& comm, const PhaseTimer& timer,
                        const RankTimings& mine, const TimingsLabels& labels);

}  // namespace rtmini
