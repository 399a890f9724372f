#include "plugins/tetra_brain/ShellLocator.h"

#include <bit>

#include "plugins/tetra_brain/UniformGrid.h"

namespace trephine::tetra {

void ShellLocator::reserve(size_t points) {
  if (points <= m_cell.size()) return;
  m_cell.resize(points);
  m_next.resize(points);
  m_cells.resize(points);
  m_cellBoxes.resize(points);
  m_firstPoint.resize(points);
  const size_t table = std::bit_ceil(2 * points);  // at most half full
  m_tableKeys.assign(table, -1);
  m_tableValues.assign(table, -1);
}

void ShellLocator::group(const UniformGrid& grid, std::span<const Vec3> points) {
  const size_t mask = m_tableKeys.size() - 1;
  m_cellCount = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const int64_t cell = grid.cellOf(points[i]);
    m_cell[i] = cell;
    m_next[i] = -1;
    if (cell < 0) continue;
    size_t slot = size_t(uint64_t(cell) * 0x9E3779B97F4A7C15ull >> 20) & mask;
    while (m_tableKeys[slot] >= 0 && m_tableKeys[slot] != cell) slot = (slot + 1) & mask;
    if (m_tableKeys[slot] < 0) {
      m_tableKeys[slot] = cell;
      m_tableValues[slot] = int32_t(m_cellCount);
      m_cells[m_cellCount] = cell;
      m_cellBoxes[m_cellCount] = Box3(points[i], points[i]);
      m_firstPoint[m_cellCount] = -1;
      ++m_cellCount;
    }
    const int32_t c = m_tableValues[slot];
    m_cellBoxes[c].extend(points[i]);
    m_next[i] = m_firstPoint[c];  // prepend; the order within a cell does not matter
    m_firstPoint[c] = int32_t(i);
  }
  // Clear only the slots used, so a frame costs the shell, not the table.
  for (size_t c = 0; c < m_cellCount; ++c) {
    size_t slot = size_t(uint64_t(m_cells[c]) * 0x9E3779B97F4A7C15ull >> 20) & mask;
    while (m_tableKeys[slot] != m_cells[c]) slot = (slot + 1) & mask;
    m_tableKeys[slot] = -1;
  }
}

}  // namespace trephine::tetra
