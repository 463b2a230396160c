#include "rtmini/report/rank_timings.hpp"

#include <algorithm>

#include "rtmini/io/timings.hpp"
#include "rtmini/report/version.hpp"

namespace rtmini {

std::vector<std::string> agreed_phase_names(const Communicator& comm, const PhaseTimer& timer) {
  // NUL-terminated names in one char buffer: one allgatherv instead of a count exchange plus
  // one message per name.
  std::vector<char> packed;
  std::vector<std::string> seen;
  for (const auto& p : timer.phases())
    if (std::find(seen.begin(), seen.end(), p.first) == seen.end()) {
      seen.push_back(p.first);
      packed.insert(packed.end(), p.first.c_str(), p.first.c_str() + p.first.size() + 1);
    }
  const std::vector<char> all = comm.allgatherv(packed);
  std::vector<std::string> names;
  for (std::size_t i = 0; i < all.size();) {
    std::string name(all.data() + i);
    i += name.size() + 1;
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

namespace {

// This rank's first start and last end of each named phase; -1 for a phase it never timed.
void phase_spans(const PhaseTimer& timer, const std::vector<std::string>& names,
                 std::vector<double>& start, std::vector<double>& end) {
  for (const auto& name : names) {
    double s = -1, e = -1;
    for (const auto& p : timer.phases()) {
      if (p.first != name) continue;
      if (s < 0) s = p.second.first;
      e = p.second.second;
    }
    start.push_back(s);
    end.push_back(e);
  }
}

}  // namespace

void write_rank_timings(const std::string& path, const Communicator& comm, const PhaseTimer& timer,
                        const RankTimings& mine, const TimingsLabels& labels) {
  const std::vector<std::string> names =
      labels.phases.empty() ? agreed_phase_names(comm, timer) : labels.phases;
  std::vector<double> my_start, my_end;
  phase_spans(timer, names, my_start, my_end);
  std::vector<RankChunk> chunks = mine.chunks;
  // The rank of each chunk travels beside it: after the gather the chunk table is one flat list.
  std::vector<std::int64_t> chunk_rank(chunks.size(), comm.rank());
  // Per-rank scalars packed by type, one gatherv for the doubles and one for the integers.
  const std::vector<double> rank_d{mine.completion, mine.idle};
  const std::vector<std::int64_t> rank_i{comm.messages_sent(), comm.bytes_sent(), mine.rays,
                                         mine.work_units};
  const auto g_start = comm.gatherv(my_start), g_end = comm.gatherv(my_end);
  const auto g_chunks = comm.gatherv(chunks);
  const auto g_chunk_rank = comm.gatherv(chunk_rank);
  const auto g_iters = comm.gatherv(mine.iterations);
  const auto g_rd = comm.gatherv(rank_d);
  const auto g_ri = comm.gatherv(rank_i);
  if (!comm.is_root()) return;

  TimingsData t;
  t.app = labels.app;
  t.version = version_string();
  t.git_hash = git_hash();
  t.backend = compat::backend_name();
  t.strategy = labels.strategy;
  t.scene = labels.scene;
  t.parameters = labels.parameters;
  t.ranks = comm.size();
  t.threads = compat::concurrency();
  t.phase_names = names;
  t.phase_start = g_start;
  t.phase_end = g_end;
  for (std::size_t i = 0; i < g_chunks.size(); ++i) {
    const RankChunk& c = g_chunks[i];
    t.chunk_rank.push_back(g_chunk_rank[i]);
    t.chunk_iteration.push_back(c.iteration);
    t.chunk_work_units.push_back(c.work_units);
    t.chunk_rays.push_back(c.rays);
    t.chunk_start.push_back(c.start);
    t.chunk_end.push_back(c.end);
  }
  for (int r = 0; r < comm.size(); ++r) {
    t.rank_completion_time.push_back(g_rd[2 * r]);
    t.rank_idle_time.push_back(g_rd[2 * r + 1]);
    t.rank_messages_sent.push_back(g_ri[4 * r]);
    t.rank_bytes_sent.push_back(g_ri[4 * r + 1]);
    t.rank_rays.push_back(g_ri[4 * r + 2]);
    t.rank_work_units.push_back(g_ri[4 * r + 3]);
  }
  t.iterations = static_cast<int>(mine.iterations.size());
  for (const RankIteration& it : g_iters) {
    t.iteration_trace_time.push_back(it.trace);
    t.iteration_allgather_time.push_back(it.allgather);
    t.iteration_write_time.push_back(it.write);
    t.iteration_allgather_bytes.push_back(it.allgather_bytes);
  }
  write_timings(path, t);
}

}  // namespace rtmini
