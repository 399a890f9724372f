// The footprint cut of force-driven drilling (FootprintCut.cpp): the row-wise
// cut (rows of air passed over, rows clipped to the sphere, neighbours by
// stride) against the plain rule over the footprint's whole box, code for
// code, over sequences of cuts on the skull phantom (into the bone, grazing
// it, at the grid's faces and corners, with tiny and large advances, whole and
// interleaved), and the rule's own promises: nothing beyond the burr's radius
// plus one voxel or behind the burr changes, codes only fall and never below
// the floor, an interleaved cut changes only its slice of rows, and the
// occupancy cells stay exactly what a build gives.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "plugins/voxel_skull/FootprintCut.h"
#include "plugins/voxel_skull/Phantoms.h"

namespace trephine::voxel {
namespace {

struct Variant {
  const char* name;
  FootprintCutResult (*cut)(SolidGrid&, const FootprintCut&);
};

std::vector<Variant> variants() { return {{"rows", &cutFootprint}}; }

// Every occupancy cell's state is what a fresh build from the codes gives:
// the cut reports each lowered code, and each code lowered through the outside
// threshold (SolidGrid::noteLowered with the code before).
void expectCellsAsBuilt(const SolidGrid& grid) {
  SolidGrid fresh = grid;
  fresh.buildOccupancy();
  const OccupancyCells& now = *grid.occupancy;
  const OccupancyCells& built = *fresh.occupancy;
  int64_t outside = 0;
  for (int64_t k = -2; k <= grid.nz; ++k)
    for (int64_t j = -2; j <= grid.ny; ++j)
      for (int64_t i = -2; i <= grid.nx; ++i) {
        const int64_t cell = now.cellIndex(i, j, k);
        outside += now.state(cell) == OccupancyCells::kOutside;
        if (now.state(cell) != built.state(cell)) {
          ADD_FAILURE() << "cell " << i << " " << j << " " << k << " is " << int(now.state(cell))
                        << ", a build from its codes gives " << int(built.state(cell));
          return;
        }
      }
  EXPECT_GT(outside, 0);
}

TEST(FootprintCutTest, RowsGiveTheCodesOfTheReferenceAndKeepTheRulesPromises) {
  const DensityVolume original = makeSkullPhantom(2.0);  // small, so whole volumes can be compared
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (const Variant& variant : variants()) {
    DensityVolume referenceVolume = original, fastVolume = original;
    SolidGrid reference = SolidGrid::of(referenceVolume, 400.0, true), fast = SolidGrid::of(fastVolume, 400.0, true);
    reference.buildOccupancy();
    fast.buildOccupancy();
    const int64_t voxels = int64_t(fast.nx) * fast.ny * fast.nz;
    const Vec3 size(fast.nx * fast.spacing.x(), fast.ny * fast.spacing.y(), fast.nz * fast.spacing.z());
    const Vec3 centre = fast.corner + 0.5 * size;
    int lowered = 0, emptied = 0;
    for (int n = 0; n < 400; ++n) {
      FootprintCut cut;
      if (n % 5 == 4) {
        // At the grid's faces and corners, partly outside.
        cut.center = fast.corner + Vec3(uniform(rng) < 0.5 ? 0.0 : size.x(), uniform(rng) * size.y(),
                                        uniform(rng) < 0.5 ? 0.0 : size.z()) +
                     Vec3(normal(rng), normal(rng), normal(rng));
      } else {
        // On the bone: a random direction from the centre until the surface, then in or out by up to 2 mm.
        Vec3 ray(normal(rng), normal(rng), normal(rng));
        ray.normalize();
        Vec3 p = centre + 150.0 * ray;
        while ((p - centre).norm() > 1.0 && !fast.solidAt(p)) p -= 0.1 * ray;
        cut.center = p + (2.5 - 2.0 + 4.0 * uniform(rng)) * ray;
        cut.direction = (-ray + 0.5 * Vec3(normal(rng), normal(rng), normal(rng))).normalized();
      }
      if (n % 5 == 4) cut.direction = Vec3(normal(rng), normal(rng), normal(rng)).normalized();
      cut.radius = 0.5 + 3.0 * uniform(rng);
      cut.advance = std::pow(10.0, -4.0 + 4.0 * uniform(rng));  // 0.1 um to 1 mm in a frame
      cut.frame = uint64_t(n);
      // Interleaved cuts: one of up to 4 sets of rows.
      cut.slices = 1 + int(uniform(rng) * 4.0);
      cut.slice = int(uniform(rng) * cut.slices);
      const std::vector<VoxelCode> before(fast.codes, fast.codes + voxels);
      const FootprintCutResult want = cutFootprintReference(reference, cut);
      const FootprintCutResult got = variant.cut(fast, cut);
      ASSERT_EQ(got.lowered, want.lowered) << variant.name << ", cut " << n;
      ASSERT_EQ(got.emptied, want.emptied) << variant.name << ", cut " << n;
      ASSERT_EQ(got.codesRemoved, want.codesRemoved) << variant.name << ", cut " << n;
      int changed = 0;
      for (int64_t v = 0; v < voxels; ++v) {
        ASSERT_EQ(fast.codes[v], reference.codes[v]) << variant.name << ", cut " << n << ", voxel " << v;
        if (fast.codes[v] == before[size_t(v)]) continue;
        ++changed;
        // Only falls, never below the floor, only in the footprint: within the
        // radius plus one voxel, and not behind the burr.
        ASSERT_LT(fast.codes[v], before[size_t(v)]);
        ASSERT_GE(fast.codes[v], VoxelCode(std::ceil(fast.outsideCode)));
        const Vec3 offset = fast.centerOf(v) - cut.center;
        ASSERT_LT(offset.norm(), cut.radius + fast.smallestSide()) << variant.name << ", cut " << n;
        ASSERT_GT(offset.dot(cut.direction), -kSideCut * (cut.radius + fast.smallestSide()));
        // Only the rows (j, k) of the cut's slice.
        const int64_t j = (v / fast.nx) % fast.ny, k = v / (int64_t(fast.nx) * fast.ny);
        ASSERT_EQ((j + k) % cut.slices, cut.slice) << variant.name << ", cut " << n;
      }
      ASSERT_EQ(changed, got.lowered) << variant.name << ", cut " << n;
      lowered += got.lowered;
      emptied += got.emptied;
    }
    expectCellsAsBuilt(fast);
    expectCellsAsBuilt(reference);
    // The cuts did cut, and emptied bone.
    EXPECT_GT(lowered, 600) << variant.name;  // 894 here
    EXPECT_GT(emptied, 20) << variant.name;
  }
}

TEST(FootprintCutTest, ACutThatCanRemoveNothingChangesNothing) {
  DensityVolume volume = makeSkullPhantom(2.0);
  SolidGrid grid = SolidGrid::of(volume, 400.0, true);
  const int64_t voxels = int64_t(grid.nx) * grid.ny * grid.nz;
  const std::vector<VoxelCode> before(grid.codes, grid.codes + voxels);
  const double nan = std::nan("");
  std::vector<FootprintCut> cuts(6);
  for (FootprintCut& c : cuts) c.radius = 2.5, c.advance = 0.01, c.center = Vec3(0, 0, 60);
  cuts[0].center.x() = nan;
  cuts[1].direction.y() = nan;
  cuts[2].radius = 0;
  cuts[3].advance = 0;
  cuts[4].advance = std::numeric_limits<double>::infinity();
  cuts[5].center = Vec3(1e300, -1e300, 1e300);  // far outside the grid
  for (const Variant& variant : variants())
    for (size_t n = 0; n < cuts.size(); ++n) {
      const FootprintCutResult r = variant.cut(grid, cuts[n]);
      EXPECT_EQ(r.lowered, 0) << variant.name << ", cut " << n;
      EXPECT_EQ(cutFootprintReference(grid, cuts[n]).lowered, 0) << "reference, cut " << n;
    }
  EXPECT_TRUE(std::equal(before.begin(), before.end(), grid.codes));
}

}  // namespace
}  // namespace trephine::voxel
