// A light stand-in for a skull's isosurface (what the live view draws before
// the drill comes): the isosurface of the volume max-pooled over f^3 voxels,
// projected back onto the full isosurface, on a spherical shell 5 mm thick
// whose exact surfaces are known (radii 40 and 35 mm). Against vertex
// clustering of the full isosurface to as many triangles, which folds the
// thin wall onto itself: the projected surface's vertices lie on the exact
// spheres, clustering's do not; and mean pooling, at the same factor, loses
// the thin wall where max pooling keeps it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "framework/data/CoarseVoxelGrid.h"
#include "framework/data/IsoSurface.h"
#include "framework/data/IsoSurfaceProjection.h"
#include "framework/data/VertexClustering.h"

namespace trephine {
namespace {

constexpr double kOuter = 40, kInner = 35;  // mm
const Vec3 kCentre(50, 50, 50);

// The shell, 1 mm voxels: codes ramp from 0 to 1000 over a millimetre across
// each sphere, so that the isosurface at 500 lies on the spheres.
struct Shell {
  std::vector<VoxelCode> codes;
  VoxelGrid grid;
  Shell() {
    grid.nx = grid.ny = grid.nz = 100;
    grid.spacing = Vec3::Ones();
    grid.inverseSpacing = Vec3::Ones();
    grid.corner = Vec3::Zero();
    grid.isoCode = 500;
    grid.outsideCode = 0;
    codes.resize(grid.voxelCount());
    for (int k = 0; k < 100; ++k)
      for (int j = 0; j < 100; ++j)
        for (int i = 0; i < 100; ++i) {
          const double r = (Vec3(i + 0.5, j + 0.5, k + 0.5) - kCentre).norm();
          const double inside = std::min(kOuter - r, r - kInner);  // mm into the bone
          codes[size_t(i + 100 * (j + 100 * k))] = VoxelCode(std::lround(500 + 500 * std::clamp(inside, -1.0, 1.0)));
        }
    grid.codes = codes.data();
  }
};

// Each vertex's distance to the nearer exact sphere (mm): p50, p99, max.
std::array<double, 3> errors(const TriangleMesh& mesh) {
  std::vector<double> e;
  for (const Vec3& p : mesh.vertices) {
    const double r = (p - kCentre).norm();
    e.push_back(std::min(std::abs(r - kOuter), std::abs(r - kInner)));
  }
  std::sort(e.begin(), e.end());
  return {e[e.size() / 2], e[size_t(0.99 * double(e.size() - 1))], e.back()};
}

// Triangles whose corners lie on different spheres: the wall folded through.
size_t foldedTriangles(const TriangleMesh& mesh) {
  const double middle = 0.5 * (kOuter + kInner);
  size_t n = 0;
  for (const auto& t : mesh.triangles) {
    int outer = 0;
    for (int32_t c : t) outer += (mesh.vertices[c] - kCentre).norm() > middle;
    n += outer == 1 || outer == 2;
  }
  return n;
}

TEST(CoarseSkullSurfaceTest, TheProjectedCoarseSurfaceLiesOnTheShellWhereClusteringFoldsIt) {
  const Shell shell;
  BlockedIsoSurface full;
  full.build(shell.grid);
  const TriangleMesh fullMesh = full.merged();
  const auto fullError = errors(fullMesh);
  EXPECT_LT(fullError[1], 0.1) << "the full isosurface is on the spheres";
  for (int factor : {3, 5, 7}) {
    const CoarseVoxelGrid pooled = coarsenVoxels(shell.grid, factor, VoxelPooling::kMax);
    BlockedIsoSurface coarse;
    coarse.build(pooled.grid);
    TriangleMesh projected = coarse.merged();
    const ProjectionCounts counts = projectOntoIsoSurface(projected, shell.grid, (factor + 1) * 1.0);
    const auto projectedError = errors(projected);
    // Vertex clustering of the full surface to as many triangles.
    const TriangleMesh clustered = simplifyToBudget({&fullMesh}, projected.triangles.size(), 0);
    const auto clusteredError = errors(clustered);
    std::printf("factor %d: %zu triangles (full %zu); projected p50/p99/max %.3f/%.3f/%.3f mm, %zu folded, %zu of %zu "
                "vertices without a crossing; clustered (%zu triangles) %.3f/%.3f/%.3f mm, %zu folded\n",
                factor, projected.triangles.size(), fullMesh.triangles.size(), projectedError[0], projectedError[1],
                projectedError[2], foldedTriangles(projected), counts.stayed, counts.moved + counts.stayed,
                clustered.triangles.size(), clusteredError[0], clusteredError[1], clusteredError[2],
                foldedTriangles(clustered));
    EXPECT_LT(projected.triangles.size(), fullMesh.triangles.size() / (factor * factor / 2));
    EXPECT_LT(projectedError[0], 0.05) << factor;
    EXPECT_LT(projectedError[1], 0.5) << factor;
    EXPECT_LT(projectedError[2], 1.0) << factor;
    EXPECT_EQ(foldedTriangles(projected), 0u) << factor;
    // Once the clusters are as wide as the wall, clustering folds it: vertices
    // between the spheres and triangles across the wall.
    if (factor >= 5) {
      EXPECT_GT(foldedTriangles(clustered), 0u) << "clustering folds the 5 mm wall at factor " << factor;
      EXPECT_GT(clusteredError[2], 2 * projectedError[2]) << factor;
    }
  }
}

TEST(CoarseSkullSurfaceTest, MeanPoolingLosesAThinWallThatMaxPoolingKeeps) {
  const Shell shell;
  // At 12 mm voxels the 5 mm wall averages below the isovalue in places.
  for (VoxelPooling pooling : {VoxelPooling::kMean, VoxelPooling::kMax}) {
    const CoarseVoxelGrid pooled = coarsenVoxels(shell.grid, 12, pooling);
    EXPECT_EQ(pooled.grid.nx, 9);
    EXPECT_EQ(pooled.grid.spacing, Vec3::Constant(12));
    // The coarse voxel at the shell's middle radius along +x.
    size_t bone = 0, shellVoxels = 0;
    for (int64_t k = 0; k < pooled.grid.nz; ++k)
      for (int64_t j = 0; j < pooled.grid.ny; ++j)
        for (int64_t i = 0; i < pooled.grid.nx; ++i) {
          const Vec3 c = pooled.grid.corner + (Vec3(double(i), double(j), double(k)) + Vec3::Constant(0.5)) * 12.0;
          const double r = (c - kCentre).norm();
          if (std::abs(r - 0.5 * (kOuter + kInner)) > 3) continue;
          ++shellVoxels;
          bone += pooled.codes[size_t(i + pooled.grid.nx * (j + pooled.grid.ny * k))] >= 500;
        }
    ASSERT_GT(shellVoxels, 8u);
    if (pooling == VoxelPooling::kMax) EXPECT_EQ(bone, shellVoxels) << "every coarse voxel on the wall is bone";
    else EXPECT_LT(bone, shellVoxels) << "some average below the isovalue";
  }
}

TEST(CoarseSkullSurfaceTest, PoolingIsTheMeanOrTheLargestOfEachBlockWithPartialBlocksAtTheEdge) {
  std::vector<VoxelCode> codes(5 * 3 * 2);
  for (size_t v = 0; v < codes.size(); ++v) codes[v] = VoxelCode(v * 7 % 11);
  VoxelGrid grid;
  grid.nx = 5, grid.ny = 3, grid.nz = 2;
  grid.codes = codes.data();
  grid.corner = Vec3(-1, 2, 3);
  grid.spacing = Vec3(0.5, 1, 2);
  for (VoxelPooling pooling : {VoxelPooling::kMean, VoxelPooling::kMax}) {
    const CoarseVoxelGrid c = coarsenVoxels(grid, 2, pooling);
    ASSERT_EQ(c.grid.nx * c.grid.ny * c.grid.nz, 3 * 2 * 1);
    EXPECT_EQ(c.grid.corner, grid.corner);
    EXPECT_EQ(c.grid.spacing, Vec3(1, 2, 4));
    EXPECT_EQ(c.grid.codes, c.codes.data());
    for (int J = 0; J < 2; ++J)
      for (int I = 0; I < 3; ++I) {
        double sum = 0, most = -1e9;
        int n = 0;
        for (int k = 0; k < 2; ++k)
          for (int j = 2 * J; j < std::min(2 * J + 2, 3); ++j)
            for (int i = 2 * I; i < std::min(2 * I + 2, 5); ++i, ++n) {
              sum += codes[size_t(i + 5 * (j + 3 * k))];
              most = std::max(most, double(codes[size_t(i + 5 * (j + 3 * k))]));
            }
        EXPECT_EQ(c.codes[size_t(I + 3 * J)], pooling == VoxelPooling::kMax ? most : std::round(sum / n))
            << I << ", " << J;
      }
  }
}

}  // namespace
}  // namespace trephine
