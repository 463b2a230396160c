#include "schedule.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <limits>
#include <thread>

#include "rtmini/io/error.hpp"

namespace rtmini::sketch {
namespace {

// Whole 16x16 tiles (256 positions) per dispatch, at least one.
std::int64_t batch_tiles(std::int64_t batch) {
  return std::max<std::int64_t>(1, batch / (kTile * kTile));
}

// Positions of tile-sized blocks [t0, t1) of the order, clipped to its end.
PosRange tile_range(std::int64_t t0, std::int64_t t1, std::int64_t size) {
  const std::int64_t block = kTile * kTile;
  return {std::min(t0 * block, size), std::min(t1 * block, size)};
}

// A fixed list of ranges per rank, dispatched in order in batches (static, metric, chunks).
class ListScheduler : public Scheduler {
 public:
  ListScheduler(std::vector<PosRange> mine, std::int64_t batch)
      : mine_(std::move(mine)), batch_(batch) {}
  bool next(std::vector<PosRange>& out, const std::function<bool()>&) override {
    out.clear();
    std::int64_t taken = 0;
    while (k_ < mine_.size() && taken < batch_) {
      PosRange& r = mine_[k_];
      const std::int64_t n = std::min(r.size(), batch_ - taken);
      out.push_back({r.begin, r.begin + n});
      r.begin += n;
      taken += n;
      if (r.size() == 0) ++k_;
    }
    return taken > 0;
  }

 private:
  std::vector<PosRange> mine_;
  std::size_t k_ = 0;
  std::int64_t batch_;
};

#ifdef RTMINI_HAVE_MPI

// Guided claim size: a share of what is left, never more than a batch, at least one tile.
std::int64_t guided(std::int64_t left, int ranks, std::int64_t max_tiles) {
  return std::clamp<std::int64_t>(left / (4 * static_cast<std::int64_t>(ranks)), 1, max_tiles);
}

class QueueScheduler : public Scheduler {
 public:
  QueueScheduler(const Communicator& comm, const PixelOrder& order, std::int64_t batch)
      : comm_(comm), size_(order.size()), max_tiles_(batch_tiles(batch)) {
    tiles_ = (size_ + kTile * kTile - 1) / (kTile * kTile);
    const MPI_Aint bytes = comm.is_root() ? sizeof(std::int64_t) : 0;
    // Window creation and release are blocking collectives that a failed peer
    // would hang: every rank agrees (a failure-aware barrier) before each.
    comm.barrier();
    MPI_Win_allocate(bytes, sizeof(std::int64_t), MPI_INFO_NULL, comm.native(), &counter_, &win_);
    if (comm.is_root()) *counter_ = 0;
    comm.barrier();
    MPI_Win_lock_all(0, win_);
  }
  bool next(std::vector<PosRange>& out, const std::function<bool()>&) override {
    out.clear();
    if (last_ >= tiles_) return false;
    std::int64_t k = guided(tiles_ - last_, comm_.size(), max_tiles_), old = 0;
    MPI_Fetch_and_op(&k, &old, MPI_INT64_T, 0, 0, MPI_SUM, win_);
    MPI_Win_flush(0, win_);
    comm_.count(sizeof k);
    last_ = old + k;
    if (old >= tiles_) return false;
    out.push_back(tile_range(old, std::min(old + k, tiles_), size_));
    return true;
  }
  void finish(bool) override {
    MPI_Win_unlock_all(win_);
    comm_.barrier();
    MPI_Win_free(&win_);
  }

 private:
  const Communicator& comm_;
  std::int64_t size_, tiles_ = 0, max_tiles_, last_ = 0;
  std::int64_t* counter_ = nullptr;
  MPI_Win win_ = MPI_WIN_NULL;
};

// Per-rank chunk queues that move between ranks by non-blocking messages, progressed
// between dispatches: neighbour bargaining (the hand-drawn paper's §3.4: push to a
// neighbour below the average) or work stealing (an idle rank asks a victim drawn by
// remaining work, which answers with the back half of its queue). A non-blocking
// allgather of {remaining cost, pixels done, stop} per round gives the average (and
// the victims' loads) and detects the end (all pixels done, or a stop).
class PeerScheduler : public Scheduler {
 public:
  PeerScheduler(const Communicator& comm, const PixelOrder& order, const CostMap* cost,
                std::int64_t batch, bool steal)
      : comm_(comm), batch_(batch), total_(order.size()), steal_(steal) {
    mpi_ = comm.duplicate();
    std::vector<double> costs;
    std::vector<PosRange> chunks;
    if (cost) {
      chunks = cost_chunks(order, *cost, 64, costs);
    } else {  // quarter tiles of unit cost per pixel
      for (std::int64_t b = 0; b < order.size(); b += kTile * kTile / 4) {
        chunks.push_back({b, std::min(order.size(), b + kTile * kTile / 4)});
        costs.push_back(static_cast<double>(chunks.back().size()));
      }
    }
    // Initial queues: the metric split in whole chunks.
    std::vector<double> prefix(chunks.size() + 1, 0.0);
    for (std::size_t k = 0; k < chunks.size(); ++k) prefix[k + 1] = prefix[k] + costs[k];
    total_cost_ = global_remaining_ = prefix.back();
    const int p = comm.size(), r = comm.rank();
    for (std::size_t k = 0; k < chunks.size(); ++k) {
      const double mid = 0.5 * (prefix[k] + prefix[k + 1]);
      const int owner =
          std::min(p - 1, static_cast<int>(mid / std::max(prefix.back(), 1e-300) * p));
      if (owner == r) {
        queue_.push_back({chunks[k].begin, chunks[k].end, costs[k]});
        remaining_ += costs[k];
      }
    }
    left_ = (r + p - 1) % p;
    right_ = (r + 1) % p;
    sent_to_.assign(p, 0);
    received_from_.assign(p, 0);
    round_all_.assign(3 * static_cast<std::size_t>(p), 0.0);
    loads_.assign(p, 0.0);
  }
  ~PeerScheduler() override {
    // A failure can unwind past sends and a round still in flight on these buffers.
    if (round_active_) {
      comm_.keep_until_exit(round_in_);
      comm_.keep_until_exit(round_all_);
    }
    if (!sends_.empty()) comm_.keep_until_exit(sends_);
    if (mpi_ != MPI_COMM_NULL) MPI_Comm_free(&mpi_);
  }

  bool next(std::vector<PosRange>& out, const std::function<bool()>& should_stop) override {
    out.clear();
    done_ += last_pixels_;
    last_pixels_ = 0;
    poll();
    while (queue_.empty() && !finished_) {
      if (should_stop()) stop_ = true;
      if (steal_ && !asking_ && !stop_ && comm_.size() > 1) ask();
      poll();
      if (queue_.empty() && !finished_) std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    if (finished_ || queue_.empty()) return false;
    // Guided sizes: once the work left everywhere (last round) is under 2 dispatches per
    // rank, dispatches shrink with it (down to one chunk), so the last ones end together.
    const double left = total_cost_ > 0 ? global_remaining_ / total_cost_ : 1.0;
    const auto guided =
        static_cast<std::int64_t>(left * static_cast<double>(total_) / (2.0 * comm_.size()));
    const std::int64_t want = std::max<std::int64_t>(1, std::min(batch_, guided));
    std::int64_t taken = 0;
    while (!queue_.empty() && taken < want) {
      const Chunk c = queue_.front();
      queue_.pop_front();
      remaining_ -= c.cost;
      out.push_back({c.begin, c.end});
      taken += c.end - c.begin;
    }
    last_pixels_ = taken;
    // Ask before running dry, so the answer arrives while this batch renders.
    if (steal_ && !asking_ && !stop_ && comm_.size() > 1 && queued_pixels() < batch_) ask();
    return true;
  }

  void progress() override {
    if (!finished_) poll();
  }
  bool has_progress() const override { return comm_.size() > 1; }

  void finish(bool stopping) override {
    if (stopping) stop_ = true;
    done_ += last_pixels_;
    last_pixels_ = 0;
    while (!finished_) {
      poll();
      if (!finished_) std::this_thread::sleep_for(std::chrono::microseconds(50));
    }
    if (round_active_) {
      comm_.wait(round_req_);
      round_active_ = false;
    }
    // Drain every message still addressed to this rank, then complete the sends.
    std::vector<std::int64_t> expected(sent_to_.size());
    MPI_Request req;
    MPI_Ialltoall(sent_to_.data(), 1, MPI_INT64_T, expected.data(), 1, MPI_INT64_T, mpi_, &req);
    comm_.wait_keeping(req, sent_to_, expected);
    for (std::size_t src = 0; src < expected.size(); ++src)
      while (received_from_[src] < expected[src]) receive(static_cast<int>(src), true);
    for (auto& s : sends_) comm_.wait(s.req);
    sends_.clear();
  }

 private:
  struct Chunk {
    std::int64_t begin, end;
    double cost;
  };
  struct Send {
    MPI_Request req;
    std::vector<double> data;
  };
  enum Tag { kLoad = 11, kTransfer = 12, kSteal = 13 };

  std::int64_t queued_pixels() const {
    std::int64_t n = 0;
    for (const Chunk& c : queue_) n += c.end - c.begin;
    return n;
  }

  // Steal request to a random other rank, drawn with probability proportional to its
  // remaining work at the last round (uniformly before the first); the answer is a
  // (possibly empty) transfer.
  void ask() {
    rng_ = rng_ * 6364136223846793005ULL + 1442695040888963407ULL +
           2 * static_cast<std::uint64_t>(comm_.rank());
    const int p = comm_.size(), me = comm_.rank();
    const double u = static_cast<double>(rng_ >> 11) * 0x1.0p-53;
    double total = 0;
    for (int r = 0; r < p; ++r)
      if (r != me) total += loads_[r];
    int victim = (me + 1 + static_cast<int>(u * (p - 1))) % p;
    if (total > 0) {
      double run = 0;
      for (int r = 0; r < p; ++r) {
        if (r == me || loads_[r] <= 0) continue;
        victim = r;
        run += loads_[r];
        if (run > u * total) break;
      }
    }
    loads_[victim] = 0;  // until the next round says otherwise
    post(victim, kSteal, {0.0});
    asking_ = true;
  }

  void post(int dest, Tag tag, std::vector<double> data) {
    sends_.push_back({MPI_REQUEST_NULL, std::move(data)});
    Send& s = sends_.back();
    MPI_Isend(s.data.data(), static_cast<int>(s.data.size()), MPI_DOUBLE, dest, tag, mpi_, &s.req);
    ++sent_to_[dest];
    comm_.count(s.data.size() * sizeof(double));
  }
  // Receives one message (from src, or any source when src < 0 and one is waiting).
  bool receive(int src, bool block) {
    MPI_Status st;
    int flag = 1;
    if (block)
      st = comm_.probe(src, MPI_ANY_TAG, mpi_);
    else
      MPI_Iprobe(src < 0 ? MPI_ANY_SOURCE : src, MPI_ANY_TAG, mpi_, &flag, &st);
    if (!flag) return false;
    int n = 0;
    MPI_Get_count(&st, MPI_DOUBLE, &n);
    std::vector<double> data(static_cast<std::size_t>(n));
    MPI_Recv(data.data(), n, MPI_DOUBLE, st.MPI_SOURCE, st.MPI_TAG, mpi_, MPI_STATUS_IGNORE);
    ++received_from_[st.MPI_SOURCE];
    if (st.MPI_TAG == kLoad) {
      (st.MPI_SOURCE == left_ ? load_left_ : load_right_) = data[0];
      if (left_ == right_) load_left_ = load_right_ = data[0];
    } else if (st.MPI_TAG == kSteal) {
      // Answer even when finished or stopping (then with nothing) so the thief moves on.
      const double half = finished_ || stop_ ? 0.0 : 0.5 * remaining_;
      if (half <= 0.0 || hand(st.MPI_SOURCE, half) <= 0.0) post(st.MPI_SOURCE, kTransfer, {});
    } else if (!finished_ && !stop_) {
      asking_ = false;
      for (std::size_t i = 0; i + 2 < data.size(); i += 3) {
        queue_.push_back({static_cast<std::int64_t>(data[i]),
                          static_cast<std::int64_t>(data[i + 1]), data[i + 2]});
        remaining_ += data[i + 2];
      }
    }
    return true;
  }
  // Gives chunks from the back of the queue worth about `amount` to `dest`.
  double hand(int dest, double amount) {
    std::vector<double> msg;
    double given = 0;
    while (queue_.size() > 1 && given + 0.5 * queue_.back().cost < amount) {
      const Chunk c = queue_.back();
      queue_.pop_back();
      msg.insert(msg.end(), {static_cast<double>(c.begin), static_cast<double>(c.end), c.cost});
      given += c.cost;
    }
    if (!msg.empty()) {
      remaining_ -= given;
      post(dest, kTransfer, std::move(msg));
    }
    return given;
  }
  void poll() {
    while (receive(-1, false)) {
    }
    for (auto it = sends_.begin(); it != sends_.end();) {
      int flag = 0;
      MPI_Test(&it->req, &flag, MPI_STATUS_IGNORE);
      it = flag ? sends_.erase(it) : std::next(it);
    }
    if (round_active_) {
      int flag = 0;
      MPI_Test(&round_req_, &flag, MPI_STATUS_IGNORE);
      if (!flag) return;
      round_active_ = false;
      double sum[3] = {0, 0, 0};
      for (int r = 0; r < comm_.size(); ++r) {
        loads_[r] = round_all_[3 * r];
        for (int k = 0; k < 3; ++k) sum[k] += round_all_[3 * r + k];
      }
      global_remaining_ = sum[0];
      if (sum[1] >= static_cast<double>(total_) || sum[2] > 0) {
        finished_ = true;
        return;
      }
      const double avg = sum[0] / comm_.size();
      if (comm_.size() > 1 && !stop_ && !steal_) {
        for (int side = 0; side < (left_ == right_ ? 1 : 2); ++side) {
          double& nb = side == 0 ? load_left_ : load_right_;
          if (remaining_ > avg && nb < avg)
            nb += hand(side == 0 ? left_ : right_, std::min(remaining_ - avg, avg - nb));
        }
      }
    }
    if (!finished_) {
      if (comm_.size() > 1 && !steal_) {
        post(left_, kLoad, {remaining_});
        if (right_ != left_) post(right_, kLoad, {remaining_});
      }
      round_in_[0] = remaining_;
      round_in_[1] = static_cast<double>(done_);
      round_in_[2] = stop_ ? 1.0 : 0.0;
      MPI_Iallgather(round_in_.data(), 3, MPI_DOUBLE, round_all_.data(), 3, MPI_DOUBLE, mpi_,
                     &round_req_);
      comm_.count(round_in_.size() * sizeof(double));
      round_active_ = true;
    }
  }

  const Communicator& comm_;
  std::int64_t batch_, total_;
  bool steal_, asking_ = false;
  std::uint64_t rng_ = 0x9e3779b97f4a7c15ULL;
  MPI_Comm mpi_ = MPI_COMM_NULL;
  std::deque<Chunk> queue_;
  double remaining_ = 0;
  double total_cost_ = 0, global_remaining_ = 0;  // all ranks' work: at start, at the last round
  std::int64_t done_ = 0, last_pixels_ = 0;
  int left_ = 0, right_ = 0;
  double load_left_ = std::numeric_limits<double>::infinity();
  double load_right_ = std::numeric_limits<double>::infinity();
  std::deque<Send> sends_;
  std::vector<std::int64_t> sent_to_, received_from_;
  bool round_active_ = false, finished_ = false, stop_ = false;
  MPI_Request round_req_ = MPI_REQUEST_NULL;
  std::vector<double> round_in_ = std::vector<double>(3, 0.0);  // this rank's part of a round
  std::vector<double> round_all_;  // every rank's {remaining, done, stop} of the last round
  std::vector<double> loads_;      // every rank's remaining cost at the last round
};

#endif  // RTMINI_HAVE_MPI

}  // namespace

Balance parse_balance(const std::string& name) {
  for (Balance b : {Balance::kStatic, Balance::kMetric, Balance::kChunks, Balance::kBargain,
                    Balance::kQueue, Balance::kSteal})
    if (name == to_string(b)) return b;
  throw InputError("--balance: expected static, metric, chunks, bargain, queue or steal, got '" +
                   name + "'");
}

const char* to_string(Balance b) {
  switch (b) {
    case Balance::kStatic:
      return "static";
    case Balance::kMetric:
      return "metric";
    case Balance::kChunks:
      return "chunks";
    case Balance::kBargain:
      return "bargain";
    case Balance::kQueue:
      return "queue";
    case Balance::kSteal:
      return "steal";
  }
  return "?";
}

bool needs_cost_map(Balance b) {
  return b == Balance::kMetric || b == Balance::kChunks || b == Balance::kBargain;
}

PixelOrder::PixelOrder(int width, int height, const std::vector<std::uint8_t>& done)
    : width_(width), height_(height), size_(static_cast<std::int64_t>(width) * height) {
  if (done.empty() || std::none_of(done.begin(), done.end(), [](std::uint8_t d) { return d != 0; }))
    return;
  for (std::int64_t pos = 0; pos < size_; ++pos) {
    const std::int64_t p = implicit(pos);
    if (!done[static_cast<std::size_t>(p)]) list_.push_back(p);
  }
  size_ = static_cast<std::int64_t>(list_.size());
  if (size_ == 0) list_.clear();
}

std::int64_t PixelOrder::implicit(std::int64_t pos) const {
  const std::int64_t band_pixels = static_cast<std::int64_t>(kTile) * width_;
  const std::int64_t band = pos / band_pixels, off = pos - band * band_pixels;
  const std::int64_t rows = std::min<std::int64_t>(kTile, height_ - band * kTile);
  const std::int64_t col = off / (kTile * rows), off2 = off - col * kTile * rows;
  const std::int64_t cols = std::min<std::int64_t>(kTile, width_ - col * kTile);
  const std::int64_t y = band * kTile + off2 / cols, x = col * kTile + off2 % cols;
  return y * width_ + x;
}

std::vector<std::int64_t> equal_cost_cuts(const PixelOrder& order, const CostMap* cost,
                                          std::int64_t parts) {
  std::vector<std::int64_t> cuts(static_cast<std::size_t>(parts) + 1, order.size());
  cuts[0] = 0;
  if (!cost) {
    for (std::int64_t k = 1; k < parts; ++k) cuts[k] = order.size() * k / parts;
    return cuts;
  }
  double total = 0;
  for (std::int64_t pos = 0; pos < order.size(); ++pos) total += cost->at(order.pixel(pos));
  double run = 0;
  std::int64_t k = 1;
  for (std::int64_t pos = 0; pos < order.size() && k < parts; ++pos) {
    run += cost->at(order.pixel(pos));
    while (k < parts && run >= total * static_cast<double>(k) / static_cast<double>(parts))
      cuts[k++] = pos + 1;
  }
  return cuts;
}

std::vector<PosRange> cost_chunks(const PixelOrder& order, const CostMap& cost, std::int64_t pixels,
                                  std::vector<double>& costs) {
  std::vector<PosRange> out;
  costs.clear();
  if (order.size() == 0) return out;
  double total = 0;
  for (std::int64_t pos = 0; pos < order.size(); ++pos) total += cost.at(order.pixel(pos));
  const double target = total / static_cast<double>(order.size()) * static_cast<double>(pixels);
  PosRange cur{0, 0};
  double run = 0;
  for (std::int64_t pos = 0; pos < order.size(); ++pos) {
    run += cost.at(order.pixel(pos));
    cur.end = pos + 1;
    // Cap a chunk at 4x the nominal size so a cheap background region still splits.
    if (run >= target || cur.size() >= 4 * pixels) {
      out.push_back(cur);
      costs.push_back(run);
      cur = {pos + 1, pos + 1};
      run = 0;
    }
  }
  if (cur.size() > 0) {
    out.push_back(cur);
    costs.push_back(run);
  }
  return out;
}

std::unique_ptr<Scheduler> make_scheduler(Balance b, const Communicator& comm,
                                          const PixelOrder& order, const CostMap* cost,
                                          std::int64_t batch) {
  const int p = comm.size(), r = comm.rank();
  if (needs_cost_map(b) && !cost)
    throw std::logic_error("make_scheduler: this strategy needs a cost map");
#ifdef RTMINI_HAVE_MPI
  if (b == Balance::kQueue) return std::make_unique<QueueScheduler>(comm, order, batch);
  if (b == Balance::kSteal)
    return std::make_unique<PeerScheduler>(comm, order, nullptr, batch, true);
  if (b == Balance::kBargain)
    return std::make_unique<PeerScheduler>(comm, order, cost, batch, false);
#endif
  std::vector<PosRange> mine;
  if (b == Balance::kChunks) {
    std::vector<double> costs;
    const std::vector<PosRange> chunks = cost_chunks(order, *cost, 64, costs);
    for (std::size_t k = static_cast<std::size_t>(r); k < chunks.size();
         k += static_cast<std::size_t>(p))
      mine.push_back(chunks[k]);
  } else {
    // static and metric; queue, steal and bargain fall back here without MPI (one rank).
    const std::vector<std::int64_t> cuts =
        equal_cost_cuts(order, b == Balance::kMetric ? cost : nullptr, p);
    if (cuts[r + 1] > cuts[r]) mine.push_back({cuts[r], cuts[r + 1]});
  }
  return std::make_unique<ListScheduler>(std::move(mine), batch);
}

}  // namespace rtmini::sketch
