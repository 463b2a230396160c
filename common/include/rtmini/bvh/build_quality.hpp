#pragma once
// Which BVH build an app asks for: the fast Morton-code LBVH or the binned-SAH build.
// Kokkos-free, so host-only settings code can name it.
namespace rtmini::bvh {

enum class BuildQuality { kLbvh, kSah };

inline const char* to_string(BuildQuality q) { return q == BuildQuality::kLbvh ? "lbvh" : "sah"; }

}  // namespace rtmini::bvh
