#pragma once
// A uniform grid of axis-aligned cells over a box, each cell listing the items
// (tetrahedra, boundary faces) whose bounding boxes overlap it (Teschner et
// al. 2003). Built once in compressed rows: a point finds its candidates in
// constant time, whatever the size of the mesh.
#include <cstdint>
#include <span>
#include <vector>

#include "framework/math/Math.h"

namespace trephine::tetra {

class UniformGrid {
 public:
  // Cells of side `cellSize` (mm) covering `bounds`; at most `maxCells` cells
  // (the side grows when the bounds would need more).
  void build(const Box3& bounds, double cellSize, const std::vector<Box3>& itemBoxes, size_t maxCells = 1u << 24);

  // The cell of p, or -1 outside the grid.
  int64_t cellOf(const Vec3& p) const {
    const Vec3 g = (p - m_origin) * m_inverseSide;
    if (!(g.x() >= 0 && g.y() >= 0 && g.z() >= 0 && g.x() < m_dims[0] && g.y() < m_dims[1] && g.z() < m_dims[2]))
      return -1;
    return int64_t(g.x()) + int64_t(m_dims[0]) * (int64_t(g.y()) + int64_t(m_dims[1]) * int64_t(g.z()));
  }
  std::span<const int32_t> items(int64_t cell) const {
    return {m_items.data() + m_start[cell], m_items.data() + m_start[cell + 1]};
  }
  // Cell coordinates range covered by a box (clamped to the grid); false if it misses the grid.
  bool cellRange(const Box3& box, std::array<int32_t, 3>& lo, std::array<int32_t, 3>& hi) const;
  int64_t cellIndex(int32_t i, int32_t j, int32_t k) const {
    return int64_t(i) + int64_t(m_dims[0]) * (int64_t(j) + int64_t(m_dims[1]) * int64_t(k));
  }
  const std::array<int32_t, 3>& dims() const { return m_dims; }
  double cellSide() const { return m_side; }
  const Vec3& origin() const { return m_origin; }
  size_t cellCount() const { return m_start.empty() ? 0 : m_start.size() - 1; }
  size_t entryCount() const { return m_items.size(); }

 private:
  Vec3 m_origin = Vec3::Zero();
  double m_side = 1, m_inverseSide = 1;
  std::array<int32_t, 3> m_dims{0, 0, 0};
  std::vector<uint32_t> m_start;  // cellCount + 1 offsets into m_items
  std::vector<int32_t> m_items;
};

}  // namespace trephine::tetra
