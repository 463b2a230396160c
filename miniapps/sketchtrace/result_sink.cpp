#include "result_sink.hpp"

#include <cstring>
#include <stdexcept>

namespace rtmini::sketch {
namespace {
constexpr int kResultTag = 21;
// A batch is sent once it holds this many pixels (about 48 MiB), interval or not.
constexpr std::size_t kMaxBatchPixels = std::size_t(1) << 20;
}  // namespace

ResultSink::ResultSink(const Communicator& comm, const PixelOrder& order,
                       std::vector<PixelResult>& frame, std::vector<std::uint8_t>& done,
                       double flush_interval)
    : comm_(comm), order_(order), frame_(frame), done_(done), interval_(flush_interval) {
#ifdef RTMINI_HAVE_MPI
  mpi_ = comm.duplicate();
#endif
}

ResultSink::~ResultSink() {
#ifdef RTMINI_HAVE_MPI
  // A failure can unwind past sends still in flight on these buffers.
  if (!sends_.empty()) comm_.keep_until_exit(sends_);
  if (mpi_ != MPI_COMM_NULL) MPI_Comm_free(&mpi_);
#endif
}

void ResultSink::merge(const std::int64_t* ranges, std::int64_t count, const PixelResult* pixels) {
  std::size_t k = 0;
  for (std::int64_t i = 0; i < count; ++i)
    for (std::int64_t pos = ranges[2 * i]; pos < ranges[2 * i + 1]; ++pos, ++k) {
      const auto p = static_cast<std::size_t>(order_.pixel(pos));
      frame_[p] = pixels[k];
      done_[p] = 1;
    }
  merged_ += static_cast<std::int64_t>(k);
}

void ResultSink::add(const std::vector<PosRange>& ranges, const std::vector<PixelResult>& pixels,
                     double now) {
  if (comm_.is_root()) {
    std::vector<std::int64_t> flat;
    for (const PosRange& r : ranges) flat.insert(flat.end(), {r.begin, r.end});
    merge(flat.data(), static_cast<std::int64_t>(ranges.size()), pixels.data());
    return;
  }
  for (const PosRange& r : ranges) ranges_.insert(ranges_.end(), {r.begin, r.end});
  pixels_.insert(pixels_.end(), pixels.begin(), pixels.end());
  if (pixels_.size() >= kMaxBatchPixels || (interval_ > 0 && now - last_flush_ >= interval_)) {
    flush(false);
    last_flush_ = now;
  }
}

// Message: int64 header {range count, final flag}, the ranges, then the pixels.
void ResultSink::flush(bool final) {
#ifdef RTMINI_HAVE_MPI
  if (ranges_.empty() && !final) return;
  const std::int64_t header[2] = {static_cast<std::int64_t>(ranges_.size() / 2), final ? 1 : 0};
  const std::size_t head = sizeof header + ranges_.size() * sizeof(std::int64_t);
  sends_.push_back(
      {std::vector<std::uint8_t>(head + pixels_.size() * sizeof(PixelResult)), MPI_REQUEST_NULL});
  Send& s = sends_.back();
  std::memcpy(s.bytes.data(), header, sizeof header);
  if (!ranges_.empty())
    std::memcpy(s.bytes.data() + sizeof header, ranges_.data(),
                ranges_.size() * sizeof(std::int64_t));
  if (!pixels_.empty())
    std::memcpy(s.bytes.data() + head, pixels_.data(), pixels_.size() * sizeof(PixelResult));
  if (s.bytes.size() > static_cast<std::size_t>(2147483647))
    throw std::runtime_error("result batch over 2 GiB");
  MPI_Isend(s.bytes.data(), static_cast<int>(s.bytes.size()), MPI_BYTE, 0, kResultTag, mpi_,
            &s.req);
  comm_.count(s.bytes.size());
  ranges_.clear();
  pixels_.clear();
#else
  (void) final;
#endif
}

void ResultSink::receive(bool block) {
#ifdef RTMINI_HAVE_MPI
  for (;;) {
    MPI_Status st;
    int flag = 1;
    if (block)
      st = comm_.probe(MPI_ANY_SOURCE, kResultTag, mpi_);
    else
      MPI_Iprobe(MPI_ANY_SOURCE, kResultTag, mpi_, &flag, &st);
    if (!flag) return;
    int n = 0;
    MPI_Get_count(&st, MPI_BYTE, &n);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(n));
    MPI_Recv(bytes.data(), n, MPI_BYTE, st.MPI_SOURCE, kResultTag, mpi_, MPI_STATUS_IGNORE);
    std::int64_t header[2];
    std::memcpy(header, bytes.data(), sizeof header);
    std::vector<std::int64_t> ranges(static_cast<std::size_t>(2 * header[0]));
    if (!ranges.empty())
      std::memcpy(ranges.data(), bytes.data() + sizeof header,
                  ranges.size() * sizeof(std::int64_t));
    const std::size_t head = sizeof header + ranges.size() * sizeof(std::int64_t);
    std::vector<PixelResult> pixels((bytes.size() - head) / sizeof(PixelResult));
    if (!pixels.empty())
      std::memcpy(pixels.data(), bytes.data() + head, pixels.size() * sizeof(PixelResult));
    merge(ranges.data(), header[0], pixels.data());
    if (header[1]) ++finals_;
    if (block) return;
  }
#else
  (void)block;
#endif
}

std::int64_t ResultSink::poll(double now) {
  (void)now;
#ifdef RTMINI_HAVE_MPI
  for (auto it = sends_.begin(); it != sends_.end();) {
    int flag = 0;
    MPI_Test(&it->req, &flag, MPI_STATUS_IGNORE);
    it = flag ? sends_.erase(it) : std::next(it);
  }
  if (comm_.is_root()) receive(false);
#endif
  return merged_;
}

void ResultSink::finish() {
#ifdef RTMINI_HAVE_MPI
  if (comm_.is_root()) {
    while (finals_ < comm_.size() - 1) receive(true);
  } else {
    flush(true);
    for (Send& s : sends_) comm_.wait(s.req);
    sends_.clear();
  }
#endif
}

}  // namespace rtmini::sketch
