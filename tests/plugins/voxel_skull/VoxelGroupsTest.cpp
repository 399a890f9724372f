// VoxelGroups: the contact points' voxels grouped in order of first sight,
// against a plain map, over frames of random voxels that collide in the table,
// and emptied between frames without a clear.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "plugins/voxel_skull/VoxelGroups.h"

namespace trephine::voxel {
namespace {

TEST(VoxelGroupsTest, EachVoxelHasOneGroupNumberedInOrderOfFirstSight) {
  constexpr size_t kPoints = 466;
  VoxelGroups groups;
  groups.reserve(kPoints);
  std::mt19937_64 rng(5);
  for (int frame = 0; frame < 200; ++frame) {
    groups.clear();
    std::map<int64_t, int32_t> expected;
    // Few distinct voxels (many repeats) in some frames, all distinct in others;
    // voxels a multiple of the table's size apart land in the same slot.
    const int64_t spread = frame % 2 ? 20 : 1 << 30;
    std::uniform_int_distribution<int64_t> pick(0, spread);
    for (size_t point = 0; point < kPoints; ++point) {
      const int64_t voxel = frame % 3 == 0 ? pick(rng) * 1024 : pick(rng);
      bool isNew = false;
      const int32_t group = groups.groupOf(voxel, isNew);
      const auto [it, inserted] = expected.try_emplace(voxel, int32_t(expected.size()));
      ASSERT_EQ(isNew, inserted) << "frame " << frame << ", voxel " << voxel;
      ASSERT_EQ(group, it->second) << "frame " << frame << ", voxel " << voxel;
    }
    ASSERT_EQ(groups.size(), expected.size());
    for (const auto& [voxel, group] : expected) EXPECT_EQ(groups.voxel(size_t(group)), voxel);
  }
}

}  // namespace
}  // namespace trephine::voxel
