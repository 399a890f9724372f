#pragma once
// Locates a whole pointshell in a tetrahedral mesh at once: the points are
// grouped by the cell of the uniform grid they fall in (a tool spans a few
// cells), so each candidate tetrahedron of a cell is loaded once and tested
// against all the points of that cell, instead of once per point. This is the
// thesis's classification of the shell in the grid, with the tetrahedra
// listed in the cells once, at rest, instead of rebinned every frame.
#include <cstdint>
#include <span>
#include <vector>

#include "framework/math/Math.h"

namespace trephine::tetra {

class UniformGrid;

class ShellLocator {
 public:
  // Working memory for shells of up to `points` points (initialisation).
  void reserve(size_t points);
  size_t capacity() const { return m_cell.size(); }

  // Cells of `points` in `grid`, grouped. Then forEachCell(f) calls
  // f(cell, box of the cell's points, first point) and nextPoint(i) walks the
  // points of a cell (-1 ends).
  void group(const UniformGrid& grid, std::span<const Vec3> points);
  template <class F>
  void forEachCell(F&& f) const {
    for (size_t c = 0; c < m_cellCount; ++c) f(m_cells[c], m_cellBoxes[c], m_firstPoint[c]);
  }
  int32_t nextPoint(int32_t point) const { return m_next[point]; }

 private:
  size_t m_cellCount = 0;
  std::vector<int64_t> m_cell;        // per point: its cell, -1 outside the grid
  std::vector<int32_t> m_next;        // per point: the next point of its cell, -1 at the end
  std::vector<int64_t> m_cells;       // distinct cells
  std::vector<Box3> m_cellBoxes;      // per distinct cell: box of its points
  std::vector<int32_t> m_firstPoint;  // per distinct cell
  std::vector<int64_t> m_tableKeys;   // open addressing: cell -> distinct index
  std::vector<int32_t> m_tableValues;
};

}  // namespace trephine::tetra
