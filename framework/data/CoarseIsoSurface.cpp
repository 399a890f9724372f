#include "framework/data/CoarseIsoSurface.h"

#include <algorithm>
#include <cmath>

#include "framework/data/CoarseVoxelGrid.h"
#include "framework/data/IsoSurface.h"

namespace trephine {

CoarseIsoSurface coarseIsoSurface(const VoxelGrid& grid, size_t triangles, size_t fullTriangles,
                                  const std::array<int64_t, 3>& blocksPerAxis) {
  CoarseIsoSurface out;
  TriangleMesh coarse;
  // Triangles fall about as 1 / f^2: start a little below that estimate.
  const int first = std::max(1, int(0.8 * std::sqrt(double(fullTriangles) / double(std::max<size_t>(triangles, 1)))));
  for (int f = first;; ++f) {
    const CoarseVoxelGrid pooled = coarsenVoxels(grid, f, VoxelPooling::kMax);
    BlockedIsoSurface surface;
    surface.build(pooled.grid);
    coarse = surface.merged();
    out.factor = f;
    if (coarse.triangles.size() <= triangles || pooled.grid.voxelCount() <= 8) break;
  }
  out.triangles = coarse.triangles.size();
  // Back onto the full surface: the max-pooled one lies up to a coarse voxel
  // outside the outer table and inside the inner one.
  if (out.factor > 1) out.projection = projectOntoIsoSurface(coarse, grid, (out.factor + 1) * grid.spacing.maxCoeff());
  // Each triangle to the block whose cells hold its centroid (cell base
  // corners kBlockCells x - 1 .. kBlockCells (x + 1) - 2).
  const int64_t cells = BlockedIsoSurface::kBlockCells;
  out.pieces.assign(size_t(blocksPerAxis[0] * blocksPerAxis[1] * blocksPerAxis[2]), TriangleMesh{});
  std::vector<int32_t> owner(coarse.vertices.size(), -1), remap(coarse.vertices.size(), -1);
  for (const auto& t : coarse.triangles) {
    const Vec3 centroid = (coarse.vertices[t[0]] + coarse.vertices[t[1]] + coarse.vertices[t[2]]) / 3;
    std::array<int64_t, 3> xyz{};
    for (int a = 0; a < 3; ++a) {
      // The cell whose base corner (a voxel centre) is just below the centroid.
      const int64_t base = int64_t(std::floor((centroid[a] - grid.corner[a]) * grid.inverseSpacing[a] - 0.5));
      xyz[a] = std::clamp<int64_t>((base + 1) / cells, 0, blocksPerAxis[a] - 1);
    }
    const int32_t block = int32_t(xyz[0] + blocksPerAxis[0] * (xyz[1] + blocksPerAxis[1] * xyz[2]));
    TriangleMesh& piece = out.pieces[size_t(block)];
    // Each piece has its own vertices (one shared by pieces is copied).
    std::array<int32_t, 3> corners{};
    for (int k = 0; k < 3; ++k) {
      const int32_t v = t[k];
      if (owner[size_t(v)] != block) {
        owner[size_t(v)] = block;
        remap[size_t(v)] = int32_t(piece.vertices.size());
        piece.vertices.push_back(coarse.vertices[size_t(v)]);
      }
      corners[k] = remap[size_t(v)];
    }
    piece.triangles.push_back(corners);
  }
  return out;
}

}  // namespace trephine
