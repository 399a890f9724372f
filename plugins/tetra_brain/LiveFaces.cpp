#include "plugins/tetra_brain/LiveFaces.h"

#include <algorithm>

namespace trephine::tetra {

void LiveFaces::build(const TetMesh& mesh, const TetTopology& topology, bool followsRemovals) {
  m_mesh = &mesh;
  m_follows = followsRemovals;
  const size_t n = mesh.tetCount();
  m_mask.resize(n);
  m_onBoundary.assign(4 * n, 0);
  for (size_t t = 0; t < n; ++t) {
    m_mask[t] = topology.boundaryMask(int32_t(t));
    for (int f = 0; f < 4; ++f) m_onBoundary[4 * t + size_t(f)] = (m_mask[t] >> f) & 1u;
  }
  // Rows: the boundary faces around each node, or every face when removals
  // are followed (boundary ones first).
  auto listed = [&](size_t slot) { return m_follows || m_onBoundary[slot]; };
  m_rowStart.assign(mesh.nodeCount() + 1, 0);
  for (size_t slot = 0; slot < 4 * n; ++slot)
    if (listed(slot))
      for (int32_t node : faceNodes(mesh.tets[slot / 4], int(slot % 4))) ++m_rowStart[size_t(node) + 1];
  for (size_t i = 0; i < mesh.nodeCount(); ++i) m_rowStart[i + 1] += m_rowStart[i];
  m_rows.resize(m_rowStart.back());
  m_live.assign(mesh.nodeCount(), 0);
  std::vector<uint32_t> back(m_rowStart.begin() + 1, m_rowStart.end());  // fills from the end
  for (int pass = 0; pass < 2; ++pass)  // boundary faces first, then the others
    for (size_t slot = 0; slot < 4 * n; ++slot) {
      if (!listed(slot) || (pass == 0) != (m_onBoundary[slot] != 0)) continue;
      for (int32_t node : faceNodes(mesh.tets[slot / 4], int(slot % 4))) {
        const size_t k = size_t(node);
        if (pass == 0) {
          m_rows[m_rowStart[k] + m_live[k]++] = int32_t(slot);
        } else {
          m_rows[--back[k]] = int32_t(slot);
        }
      }
    }
  m_exposed.clear();
  m_exposedAt.clear();
  m_firstBoundary.clear();
  if (m_follows) {
    m_exposed.reserve(4 * n);
    m_exposedAt.assign(4 * n, -1);
    m_firstBoundary = m_onBoundary;
  }
  m_removedTets = m_exposedEver = 0;
  m_mostExposed = 0;
}

void LiveFaces::setBoundary(int32_t slot, bool boundary) {
  uint8_t& flag = m_onBoundary[size_t(slot)];
  if ((flag != 0) == boundary) return;
  flag = boundary;
  const BoundaryFace face = faceOf(slot);
  for (int32_t node : faceNodes(m_mesh->tets[size_t(face.tet)], face.face)) {
    int32_t* row = m_rows.data() + m_rowStart[size_t(node)];
    const size_t size = m_rowStart[size_t(node) + 1] - m_rowStart[size_t(node)];
    uint32_t& live = m_live[size_t(node)];
    const size_t at = size_t(std::find(row, row + size, slot) - row);
    if (at == size) continue;  // cannot happen: every face is in its nodes' rows
    if (boundary) {
      std::swap(row[at], row[live++]);
    } else {
      std::swap(row[at], row[--live]);
    }
  }
  if (m_firstBoundary[size_t(slot)]) return;
  // A face inside the mesh at first: the cavity's list.
  int32_t& at = m_exposedAt[size_t(slot)];
  if (boundary) {
    at = int32_t(m_exposed.size());
    m_exposed.push_back(face);  // within the capacity: every slot
    ++m_exposedEver;
    m_mostExposed = std::max(m_mostExposed, m_exposed.size());
  } else if (at >= 0) {
    const BoundaryFace last = m_exposed.back();
    m_exposed[size_t(at)] = last;
    m_exposedAt[size_t(slotOf(last))] = at;
    m_exposed.pop_back();
    at = -1;
  }
}

void LiveFaces::apply(const RemainingMesh::Change& change) {
  if (!m_follows) return;
  for (const BoundaryFace& f : change.takenAway) setBoundary(slotOf(f), false);
  for (int32_t tet : change.removedTets) m_mask[size_t(tet)] = 0;
  for (const BoundaryFace& f : change.exposed) {
    setBoundary(slotOf(f), true);
    m_mask[size_t(f.tet)] |= uint8_t(1u << f.face);
  }
  m_removedTets += change.removedTets.size();
}

}  // namespace trephine::tetra
