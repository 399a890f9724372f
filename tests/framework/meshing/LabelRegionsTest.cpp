// The regions of a labelled image: each label's voxels joined across faces
// (not edges or corners), counted, and the small ones merged into the label
// most of their neighbours have.
#include <gtest/gtest.h>

#include "framework/meshing/LabelRegions.h"

namespace trephine {
namespace {

// An n^3 image of zeros.
LabelledImage empty(int n) {
  LabelledImage image;
  image.dims = {n, n, n};
  image.labels.assign(size_t(n) * n * n, 0);
  return image;
}

int32_t& at(LabelledImage& image, int i, int j, int k) {
  return image.labels[size_t(i) + size_t(image.dims[0]) * (size_t(j) + size_t(image.dims[1]) * size_t(k))];
}

TEST(LabelRegionsTest, VoxelsJoinAcrossFacesOnlyAndEachLabelApart) {
  LabelledImage image = empty(6);
  // Two voxels of label 1 touching at an edge only: two regions.
  at(image, 1, 1, 1) = 1;
  at(image, 2, 2, 1) = 1;
  // A bar of three voxels of label 1 across faces: one region.
  for (int i = 0; i < 3; ++i) at(image, i, 4, 4) = 1;
  // A voxel of label 2 next to the bar: a region of its own.
  at(image, 3, 4, 4) = 2;
  const LabelRegionCount count = countLabelRegions(image, 2);
  EXPECT_EQ(count.regions, 4u);
  EXPECT_EQ(count.small, 3u) << "the single voxels";
  EXPECT_EQ(count.smallVoxels, 3u);
}

TEST(LabelRegionsTest, ASmallRegionTakesTheLabelMostOfItsNeighboursHave) {
  LabelledImage image = empty(7);
  // A 5^3 block of label 3 (from 1 to 5), holding a speck of label 9 at its
  // centre and one of label 8 on its face; a speck of 9 apart, at the image's
  // corner (its neighbours: outside and the border, both 0).
  for (int k = 1; k <= 5; ++k)
    for (int j = 1; j <= 5; ++j)
      for (int i = 1; i <= 5; ++i) at(image, i, j, k) = 3;
  at(image, 3, 3, 3) = 9;
  at(image, 3, 3, 5) = 8;  // on the top face: 5 neighbours of 3, 1 outside
  at(image, 0, 0, 0) = 9;
  const LabelRegionCount merged = mergeSmallLabelRegions(image, 8);
  EXPECT_EQ(merged.regions, 4u);
  EXPECT_EQ(merged.small, 3u);
  EXPECT_EQ(at(image, 3, 3, 3), 3);
  EXPECT_EQ(at(image, 3, 3, 5), 3);
  EXPECT_EQ(at(image, 0, 0, 0), 0);
  EXPECT_EQ(countLabelRegions(image, 8).regions, 1u) << "the block alone";
  // A region at the size asked for stays.
  LabelledImage pair = empty(4);
  at(pair, 1, 1, 1) = at(pair, 2, 1, 1) = 5;
  EXPECT_EQ(mergeSmallLabelRegions(pair, 2).small, 0u);
  EXPECT_EQ(at(pair, 1, 1, 1), 5);
}

}  // namespace
}  // namespace trephine
