// A rank's map and halo (map_exchange.hpp): its own vertices in the map, every remote vertex it
// reads in the halo, laid out in the order the exchange receives the colours (owner rank, then
// entry), since the exchange's receive buffer is the halo itself and nothing is scattered.
#include <gtest/gtest.h>

#include <algorithm>

#include "map_exchange.hpp"

namespace rtmini::bake {
namespace {

// 40 vertices, the first 10 view-independent (one colour), the others with n viewpoints.
BakeSceneHost scene_of(int n) {
  BakeSceneHost s;
  s.normal.assign(40, Vec3(0, 0, 1));
  s.color_offset.assign(41, 0);
  for (int v = 0; v < 40; ++v) s.color_offset[v + 1] = s.color_offset[v] + (v < 10 ? 1 : n);
  return s;
}

// Owners in interleaved ranges, as a cut of several batches per rank gives them.
std::vector<int> owners() {
  std::vector<int> owner(40);
  for (int v = 0; v < 40; ++v) owner[v] = v < 5 ? 1 : v < 14 ? 0 : v < 22 ? 2 : v < 30 ? 1 : 0;
  return owner;
}

// The vertices `rank` owns: what its map holds (make_halo_layout's `own`).
std::vector<char> owned_by(const std::vector<int>& owner, int rank) {
  std::vector<char> own(owner.size());
  for (std::size_t v = 0; v < owner.size(); ++v) own[v] = owner[v] == rank;
  return own;
}

TEST(BakeMapLayout, HaloHoldsTheColoursReadInReceiveOrder) {
  const int n = 70, rank = 0;  // two mask words per sparse vertex
  const BakeSceneHost s = scene_of(n);
  const std::vector<int> owner = owners();
  // Read by rank 0: every third vertex of the others (view-independent ones among them).
  std::vector<char> remote(40, 0);
  for (int v = 0; v < 40; ++v) remote[v] = owner[v] != rank && v % 3 != 1;
  const MapLayout dense = make_map_layout(s, remote);
  std::vector<char> read(static_cast<std::size_t>(dense.colors()), 0);
  for (int v = 0; v < 40; ++v)
    for (std::int64_t j = 0; j < dense.offset[v + 1] - dense.offset[v]; ++j)
      read[dense.offset[v] + j] = (v * 7 + j * 3) % 5 == 0;
  const MapLayout l = make_halo_layout(s, dense, read.data(), owner, owned_by(owner, rank));

  // The map: rank 0's vertices, dense, in vertex order.
  std::int64_t own = 0;
  for (int v = 0; v < 40; ++v) {
    EXPECT_EQ(l.in_map(v), owner[v] == rank) << v;
    if (owner[v] == rank) {
      EXPECT_EQ(l.offset[v], own);
      own += s.color_count(v);
    }
  }
  EXPECT_EQ(l.colors(), own);

  // The halo: exactly the colours read (all of a view-independent vertex), by owner, then entry.
  std::vector<std::int64_t> expected;
  for (int r : {1, 2})
    for (int v = 0; v < 40; ++v)
      if (remote[v] && owner[v] == r)
        for (std::int64_t j = 0; j < s.color_count(v); ++j)
          if (s.color_count(v) == 1 || read[dense.offset[v] + j])
            expected.push_back(s.color_offset[v] + j);
  const std::vector<std::int64_t> halo = remote_entries(s, l);
  EXPECT_EQ(halo, expected);
  EXPECT_EQ(l.halo_colors, static_cast<std::int64_t>(expected.size()));
  ASSERT_EQ(l.halo_rank_at.size(), 4u);
  EXPECT_EQ(l.halo_rank_at[0], 0);
  EXPECT_EQ(l.halo_rank_at[1], 0);
  EXPECT_EQ(l.halo_rank_at[3], l.halo_colors);

  // Entries are numbered map first, then halo in that order; a restart's map lands on them.
  std::vector<Vec3f> global(static_cast<std::size_t>(s.colors()));
  for (std::size_t g = 0; g < global.size(); ++g) global[g] = Vec3f(float(g), 0.f, 1.f);
  const std::vector<Vec3f> local = localise_map(s, l, global);
  ASSERT_EQ(static_cast<std::int64_t>(local.size()), l.colors() + l.halo_colors);
  for (std::size_t k = 0; k < halo.size(); ++k) {
    const std::int64_t g = halo[k];
    const std::int64_t v = std::upper_bound(s.color_offset.begin(), s.color_offset.end(), g) -
                           s.color_offset.begin() - 1;
    ASSERT_TRUE(l.keeps(v, g - s.color_offset[v]));
    EXPECT_EQ(l.entry(v, g - s.color_offset[v]), l.colors() + static_cast<std::int64_t>(k));
    EXPECT_EQ(local[l.colors() + k].x, float(g));
  }
  for (int v = 0; v < 40; ++v) {
    if (owner[v] != rank) continue;
    for (std::int64_t j = 0; j < s.color_count(v); ++j) {
      EXPECT_EQ(local[l.offset[v] + j].x, float(s.color_offset[v] + j));
    }
  }
}

TEST(BakeMapLayout, WithoutReadFlagsTheHaloKeepsEveryColour) {
  const BakeSceneHost s = scene_of(8);
  const std::vector<int> owner = owners();
  std::vector<char> remote(40, 0);
  for (int v = 0; v < 40; ++v) remote[v] = owner[v] != 2;
  const MapLayout l =
      make_halo_layout(s, make_map_layout(s, remote), nullptr, owner, owned_by(owner, 2));
  std::int64_t expected = 0;
  for (int v = 0; v < 40; ++v) expected += owner[v] != 2 ? s.color_count(v) : 0;
  EXPECT_EQ(l.halo_colors, expected);
  EXPECT_EQ(l.colors() + l.halo_colors, s.colors());
  for (int v = 0; v < 40; ++v) {
    EXPECT_TRUE(l.dense(v));
  }
}

}  // namespace
}  // namespace rtmini::bake
