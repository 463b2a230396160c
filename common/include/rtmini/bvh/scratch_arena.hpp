#pragma once
// A device build's temporary arrays carved out of one allocation. On CUDA without stream-ordered
// allocation (Kokkos 4's default) every View is a cudaMalloc and its release a synchronizing
// cudaFree: the LBVH build of 1M triangles spent ~0.3 ms of its 1.7 ms on them outside its
// timed phases (results/gpu/README.md). The Views handed out do not own their memory: they are
// valid while the arena, or the allocation it returns, lives. build_lbvh also makes the tree's own
// arrays this way (Bvh::storage keeps them).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rtmini/kokkos_compat.hpp"

namespace rtmini::bvh {

template <class MemorySpace>
class ScratchArena {
 public:
  // Every array starts on this boundary (CUB's temporary storage asks for 256 bytes).
  static constexpr std::size_t kAlignment = 256;

  // Reserves room for `view` with n entries; allocate() points it there.
  template <class DataType>
  void add(Kokkos::View<DataType, MemorySpace>& view, std::size_t n) {
    using V = Kokkos::View<DataType, MemorySpace>;
    const std::size_t offset = bytes_;
    bytes_ += round_up(V::required_allocation_size(n));
    binders_.push_back([&view, n, offset](unsigned char* base) {
      view = V(reinterpret_cast<typename V::pointer_type>(base + offset), n);
    });
  }

  // One allocation for everything added, then every added View pointed into it (the base
  // rounded up to kAlignment: Kokkos' allocation header leaves the data at a smaller one).
  // Returns the allocation: the added Views are valid while it (or the arena) lives.
  Kokkos::View<unsigned char*, MemorySpace> allocate(const std::string& label) {
    storage_ = Kokkos::View<unsigned char*, MemorySpace>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, label), bytes_ + kAlignment);
    const std::uintptr_t at = reinterpret_cast<std::uintptr_t>(storage_.data());
    unsigned char* base = storage_.data() + (round_up(at) - at);
    for (const auto& bind : binders_) bind(base);
    binders_.clear();
    return storage_;
  }

  std::size_t bytes() const { return bytes_; }

 private:
  static std::size_t round_up(std::size_t bytes) {
    return (bytes + kAlignment - 1) / kAlignment * kAlignment;
  }

  std::size_t bytes_ = 0;
  std::vector<std::function<void(unsigned char*)> > binders_;
  Kokkos::View<unsigned char*, MemorySpace> storage_;
};

}  // namespace rtmini::bvh
