#include "plugins/tetra_brain/UniformGrid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace trephine::tetra {

bool UniformGrid::cellRange(const Box3& box, std::array<int32_t, 3>& lo, std::array<int32_t, 3>& hi) const {
  for (int a = 0; a < 3; ++a) {
    const double from = std::floor((box.min()[a] - m_origin[a]) * m_inverseSide);
    const double to = std::floor((box.max()[a] - m_origin[a]) * m_inverseSide);
    if (!(to >= 0 && from < m_dims[a])) return false;
    lo[a] = int32_t(std::max(0.0, from));
    hi[a] = int32_t(std::min(double(m_dims[a] - 1), to));
  }
  return true;
}

void UniformGrid::build(const Box3& bounds, double cellSize, const std::vector<Box3>& itemBoxes, size_t maxCells) {
  if (!(cellSize > 0) || bounds.isEmpty()) throw std::invalid_argument("grid needs a positive cell size and bounds");
  // A small margin so points on the far faces still fall inside.
  const Vec3 extent = bounds.sizes() + Vec3::Constant(1e-6 * (1.0 + bounds.sizes().maxCoeff()));
  double side = cellSize;
  auto cellsFor = [&](double s) {
    return double(std::ceil(extent.x() / s)) * std::ceil(extent.y() / s) * std::ceil(extent.z() / s);
  };
  while (cellsFor(side) > double(maxCells)) side *= 1.25;
  m_side = side;
  m_inverseSide = 1.0 / side;
  m_origin = bounds.min();
  for (int a = 0; a < 3; ++a) m_dims[a] = std::max(1, int32_t(std::ceil(extent[a] / side)));
  const size_t cells = size_t(m_dims[0]) * m_dims[1] * m_dims[2];
  // Two passes: count per cell, then fill (compressed rows, no per-cell vectors).
  std::vector<uint32_t> count(cells + 1, 0);
  std::array<int32_t, 3> lo, hi;
  for (const Box3& box : itemBoxes) {
    if (!cellRange(box, lo, hi)) continue;
    for (int32_t k = lo[2]; k <= hi[2]; ++k)
      for (int32_t j = lo[1]; j <= hi[1]; ++j)
        for (int32_t i = lo[0]; i <= hi[0]; ++i) ++count[cellIndex(i, j, k)];
  }
  m_start.assign(cells + 1, 0);
  for (size_t c = 0; c < cells; ++c) m_start[c + 1] = m_start[c] + count[c];
  m_items.assign(m_start[cells], 0);
  std::vector<uint32_t> fill(m_start.begin(), m_start.end() - 1);
  for (size_t item = 0; item < itemBoxes.size(); ++item) {
    if (!cellRange(itemBoxes[item], lo, hi)) continue;
    for (int32_t k = lo[2]; k <= hi[2]; ++k)
      for (int32_t j = lo[1]; j <= hi[1]; ++j)
        for (int32_t i = lo[0]; i <= hi[0]; ++i) m_items[fill[cellIndex(i, j, k)]++] = int32_t(item);
  }
}

}  // namespace trephine::tetra
