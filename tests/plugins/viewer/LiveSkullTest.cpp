// The live view's skull (LiveSkull) on a spherical shell: at the start the
// coarse, projected surface within the triangle budget, in pieces that each
// lie in one full-resolution block; a drilled block's piece goes and the
// block comes whole, and nothing else changes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "plugins/viewer/LiveSkull.h"

namespace trephine::viewer {
namespace {

struct Shell {
  std::vector<VoxelCode> codes;
  VoxelGrid grid;
  Shell() {
    grid.nx = grid.ny = grid.nz = 70;
    grid.inverseSpacing = grid.spacing = Vec3::Ones();
    grid.isoCode = 500;
    codes.resize(grid.voxelCount());
    for (int k = 0; k < 70; ++k)
      for (int j = 0; j < 70; ++j)
        for (int i = 0; i < 70; ++i) {
          const double r = (Vec3(i + 0.5, j + 0.5, k + 0.5) - Vec3(35, 35, 35)).norm();
          codes[size_t(i + 70 * (j + 70 * k))] = VoxelCode(std::lround(500 + 500 * std::clamp(std::min(30 - r, r - 25), -1.0, 1.0)));
        }
    grid.codes = codes.data();
  }
};

size_t total(const std::map<size_t, TriangleMesh>& shown) {
  size_t n = 0;
  for (const auto& [block, mesh] : shown) n += mesh.triangles.size();
  return n;
}

TEST(LiveSkullTest, CoarsePiecesAtTheStartADrilledBlockReplacesItsPiece) {
  const Shell shell;
  BlockedIsoSurface fine;
  fine.build(shell.grid);
  std::map<size_t, TriangleMesh> shown;  // what the browser holds, by block
  size_t messages = 0;
  LiveSkull skull(shell.grid, fine, 6000, [&](size_t block, const TriangleMesh& mesh) {
    ++messages;
    if (mesh.triangles.empty()) shown.erase(block);
    else shown[block] = mesh;
  });
  skull.sendStart();
  EXPECT_GT(skull.factor(), 1);
  EXPECT_LE(skull.coarseTriangles(), 6000u);
  EXPECT_EQ(total(shown), skull.coarseTriangles());
  EXPECT_GT(skull.projection().moved, 9 * skull.projection().stayed) << "most vertices land on the surface";
  for (const auto& [block, mesh] : shown) {
    ASSERT_GE(block, fine.blockCount()) << "coarse pieces travel after the fine blocks";
    for (const Vec3& p : mesh.vertices) {
      const double r = (p - Vec3(35, 35, 35)).norm();
      EXPECT_LT(std::min(std::abs(r - 30), std::abs(r - 25)), 1.0) << "on the shell";
    }
  }
  // A block the surface passes through, as if drilled.
  size_t drilled = 0;
  while (drilled < fine.blockCount() && (fine.block(drilled).triangles.empty() || !shown.count(fine.blockCount() + drilled)))
    ++drilled;
  ASSERT_LT(drilled, fine.blockCount());
  const size_t piece = shown.at(fine.blockCount() + drilled).triangles.size();
  const auto before = shown;
  skull.fineBlockChanged(drilled);
  EXPECT_FALSE(shown.count(fine.blockCount() + drilled)) << "its coarse piece is gone";
  ASSERT_TRUE(shown.count(drilled));
  EXPECT_EQ(shown.at(drilled).triangles.size(), fine.block(drilled).triangles.size()) << "the block whole";
  EXPECT_EQ(total(shown), skull.coarseTriangles() - piece + fine.block(drilled).triangles.size());
  for (const auto& [block, mesh] : before) {
    if (block != fine.blockCount() + drilled) {
      EXPECT_TRUE(shown.count(block)) << "block " << block << " stays";
    }
  }
  // Again: the block only.
  const size_t sent = messages;
  skull.fineBlockChanged(drilled);
  EXPECT_EQ(messages, sent + 1);
}

}  // namespace
}  // namespace trephine::viewer
