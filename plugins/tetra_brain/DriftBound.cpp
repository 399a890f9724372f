#include "plugins/tetra_brain/DriftBound.h"

#include <algorithm>
#include <cmath>

namespace trephine::tetra {

namespace {
// The drift of the nodes of slice `chunk`.
double sliceDrift(const TetGridSet& grids, std::span<const Vec3> nodes, size_t chunk) {
  const size_t begin = nodes.size() * chunk / DriftBound::kChunks;
  const size_t end = nodes.size() * (chunk + 1) / DriftBound::kChunks;
  return driftFromReference(grids, nodes.subspan(begin, end - begin), begin);
}
}  // namespace

double DriftBound::update(const TetGridSet& grids, std::span<const Vec3> nodes, double largestMove, double limit) {
  if (!m_known || !std::isfinite(largestMove)) {
    measureAll(grids, nodes);
    return bound();
  }
  m_moves += largestMove;
  m_drift[m_next] = sliceDrift(grids, nodes, m_next);
  m_movesAt[m_next] = m_moves;
  m_next = (m_next + 1) % kChunks;
  if (bound() > limit) measureAll(grids, nodes);
  return bound();
}

void DriftBound::measureAll(const TetGridSet& grids, std::span<const Vec3> nodes) {
  m_moves = 0;
  for (size_t c = 0; c < kChunks; ++c) {
    m_drift[c] = sliceDrift(grids, nodes, c);
    m_movesAt[c] = 0;
  }
  m_next = 0;
  m_known = true;
  ++m_fullMeasurements;
}

double DriftBound::bound() const {
  double largest = 0;
  for (size_t c = 0; c < kChunks; ++c) largest = std::max(largest, m_drift[c] + (m_moves - m_movesAt[c]));
  return largest;
}

}  // namespace trephine::tetra
