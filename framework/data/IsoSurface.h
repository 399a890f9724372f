#pragma once
// The bone's surface as triangles, for the back-ends that work on meshes: the
// isosurface of the codes interpolated trilinearly between voxel centres (the
// native back-end's smooth surface) at the grid's isoCode.
//
// Extraction by marching tetrahedra: each interpolation cell (the box
// between 8 neighbouring voxel centres) is split into 6 tetrahedra around
// its main diagonal, the same split in every cell, and each tetrahedron
// gives 0, 1 or 2 triangles. Chosen over marching cubes' 256-case table
// because a tetrahedron has no ambiguous face: the surface is closed and
// consistent across cells with no case analysis, at about twice the
// triangles. Vertices on the cells' own edges lie exactly on the trilinear
// isosurface (the interpolation is linear along them); those on the
// tetrahedra's diagonals are within the interpolation's curvature of it.
//
// The cells around the grid, whose outer corners take the grid's
// outsideCode, are included, so a volume whose border is air gives a closed
// surface. Triangles face out of the bone (from higher codes to lower ones).
// The cells are extracted in blocks of kBlockCells^3, so a drilled region is
// re-extracted block by block; vertices on a block's faces are computed
// identically on both sides, so the blocks meet without cracks. Triangles of
// zero area (an isovalue equal to a corner's code) are dropped.
#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "framework/data/TriangleBlocks.h"
#include "framework/data/VoxelGrid.h"

namespace trephine {

// Optional: cells known to hold no surface (all 8 corners clearly on one
// side, as the voxel skull's occupancy cells know), skipped without reading
// their codes; by the cell's base corner (i, j, k), each from -1.
using CellsWithoutSurface = std::function<bool(int64_t i, int64_t j, int64_t k)>;

class BlockedIsoSurface final : public TriangleBlocks {
 public:
  static constexpr int kBlockCells = 16;

  // Extracts every block (O(voxels)).
  void build(const VoxelGrid& grid, const CellsWithoutSurface& skip = {});
  // Re-extracts the blocks with a cell that has a corner in the voxel box
  // [first, last] (inclusive indices, clamped to the grid): the codes there
  // changed. Returns the indices of the blocks re-extracted.
  std::vector<size_t> update(const VoxelGrid& grid, const std::array<int64_t, 3>& first,
                             const std::array<int64_t, 3>& last, const CellsWithoutSurface& skip = {});
  // The same in two steps, for a copy kept elsewhere: f(index) for every
  // block a change of the codes in [first, last] re-extracts (no allocation),
  // then the re-extraction of the blocks gathered.
  template <class F>
  void forBlocksTouching(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last, F&& f) const {
    // A cell with base corner c (from -1) has corners c and c + 1, so it has
    // one in [first, last] when c is in [first - 1, last]; its block is (c + 1) / kBlockCells.
    std::array<int64_t, 3> lo{}, hi{};
    for (int a = 0; a < 3; ++a) {
      if (first[a] > last[a] || m_blocksPerAxis[a] == 0) return;
      lo[a] = std::clamp<int64_t>(first[a] / kBlockCells, 0, m_blocksPerAxis[a] - 1);
      hi[a] = std::clamp<int64_t>((last[a] + 1) / kBlockCells, 0, m_blocksPerAxis[a] - 1);
    }
    for (int64_t z = lo[2]; z <= hi[2]; ++z)
      for (int64_t y = lo[1]; y <= hi[1]; ++y)
        for (int64_t x = lo[0]; x <= hi[0]; ++x) f(size_t(x + m_blocksPerAxis[0] * (y + m_blocksPerAxis[1] * z)));
  }
  void reextract(const VoxelGrid& grid, std::span<const size_t> blocks, const CellsWithoutSurface& skip = {});

  size_t blockCount() const override { return m_blocks.size(); }
  // Blocks along x, y and z; block (x, y, z) is index x + nx (y + ny z) and
  // holds the cells with base corners kBlockCells x - 1 to kBlockCells (x + 1) - 2.
  const std::array<int64_t, 3>& blocksPerAxis() const { return m_blocksPerAxis; }
  // The same for a grid, without extracting anything.
  static std::array<int64_t, 3> blocksPerAxisOf(const VoxelGrid& grid) {
    return {(int64_t(grid.nx) + kBlockCells) / kBlockCells, (int64_t(grid.ny) + kBlockCells) / kBlockCells,
            (int64_t(grid.nz) + kBlockCells) / kBlockCells};
  }
  const TriangleMesh& block(size_t index) const override { return m_blocks[index]; }
  // Every block's triangles in one mesh (the vertices of block faces repeated).
  TriangleMesh merged() const;
  uint64_t degenerateTriangles() const { return m_degenerate; }

 private:
  void extractBlock(const VoxelGrid& grid, size_t index, const CellsWithoutSurface& skip);
  // Cells have base corners -1..n-1 per axis: n + 1 of them.
  std::array<int64_t, 3> m_cells{0, 0, 0};
  std::array<int64_t, 3> m_blocksPerAxis{0, 0, 0};
  std::vector<TriangleMesh> m_blocks;
  uint64_t m_degenerate = 0;
};

}  // namespace trephine
