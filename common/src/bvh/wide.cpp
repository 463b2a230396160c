#include "rtmini/bvh/wide.hpp"

#include <utility>

namespace rtmini::bvh {

namespace {

struct Slot {
  Aabb box;
  std::uint32_t ref;
};

void set_lane(WideNode& n, int k, const Aabb& b, std::uint32_t ref) {
  n.lo_x[k] = b.lo.x;
  n.lo_y[k] = b.lo.y;
  n.lo_z[k] = b.lo.z;
  n.hi_x[k] = b.hi.x;
  n.hi_y[k] = b.hi.y;
  n.hi_z[k] = b.hi.z;
  n.child[k] = ref;
}

}  // namespace

std::vector<WideNode> collapse_to_wide(const std::vector<BvhNode>& binary) {
  std::vector<WideNode> out;
  if (binary.empty()) return out;
  out.reserve(binary.size() / 2 + 1);
  // Each work item: a binary node to turn into the wide node `dst`.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> work{{0u, 0u}};
  out.emplace_back();
  while (!work.empty()) {
    const auto [src, dst] = work.back();
    work.pop_back();
    Slot slots[kWidth];
    int n = 0;
    for (int k = 0; k < 2; ++k) slots[n++] = {binary[src].box(k), binary[src].child[k]};
    // Open the internal child with the largest surface area until kWidth children.
    while (n < kWidth) {
      int best = -1;
      Real best_area = -1;
      for (int k = 0; k < n; ++k) {
        if (is_leaf(slots[k].ref)) continue;
        const Real a = slots[k].box.surface_area();
        if (a > best_area) {
          best_area = a;
          best = k;
        }
      }
      if (best < 0) break;
      const BvhNode& open = binary[slots[best].ref];
      slots[best] = {open.box(0), open.child[0]};
      slots[n++] = {open.box(1), open.child[1]};
    }
    for (int k = 0; k < kWidth; ++k) {
      if (k >= n || slots[k].ref == kEmptyLeaf) {
        Aabb empty;  // lo > hi on every axis: never hit by the wide slab test
        set_lane(out[dst], k, empty, kEmptyLeaf);
        continue;
      }
      std::uint32_t ref = slots[k].ref;
      if (!is_leaf(ref)) {
        const auto id = static_cast<std::uint32_t>(out.size());
        out.emplace_back();
        work.push_back({ref, id});
        ref = id;
      }
      set_lane(out[dst], k, slots[k].box, ref);
    }
  }
  return out;
}

}  // namespace rtmini::bvh
