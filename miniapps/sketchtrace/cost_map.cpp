#include "cost_map.hpp"

#include "cost_map_file.hpp"

namespace rtmini::sketch {

CostMap make_cost_map(const Renderer& renderer, const Communicator& comm, int width, int height,
                      const std::string& path, const std::string& signature, bool& reused) {
  CostMap m;
  m.width = width;
  m.height = height;
  m.stride = 4;
  m.grid_w = (width + m.stride - 1) / m.stride;
  m.grid_h = (height + m.stride - 1) / m.stride;
  const std::int64_t probes = static_cast<std::int64_t>(m.grid_w) * m.grid_h;
  m.cost.assign(static_cast<std::size_t>(probes), 0.f);
  const CostMapKey key{signature, width, height, m.stride};
  std::vector<std::uint8_t> ok{0};
  if (comm.is_root()) ok[0] = read_cost_map_file(path, key, m.cost.size(), m.cost) ? 1 : 0;
  comm.broadcast(ok);
  reused = ok[0] != 0;
  if (reused) {
    comm.broadcast(m.cost);
    return m;
  }
  // Rank r probes blocks [r G / P, (r + 1) G / P), at each block's centre pixel.
  const std::int64_t b0 = probes * comm.rank() / comm.size(),
                     b1 = probes * (comm.rank() + 1) / comm.size();
  std::vector<std::int64_t> pixels;
  for (std::int64_t b = b0; b < b1; ++b) {
    const int gx = static_cast<int>(b % m.grid_w), gy = static_cast<int>(b / m.grid_w);
    const int x = std::min(width - 1, gx * m.stride + m.stride / 2);
    const int y = std::min(height - 1, gy * m.stride + m.stride / 2);
    pixels.push_back(static_cast<std::int64_t>(y) * width + x);
  }
  std::vector<float> mine;
  renderer.probe(pixels, mine);
  m.cost = comm.allgatherv(mine);
  if (comm.is_root() && !path.empty()) write_cost_map_file(path, key, m.cost);
  return m;
}

}  // namespace rtmini::sketch
