#include "plugins/tetra_brain/BrainResection.h"

#include <algorithm>
#include <cmath>

namespace trephine::tetra {

BrainResection::BrainResection(const TetMesh& mesh, const TetTopology& topology, const TissueTable& tissues)
    : m_remaining(mesh, topology), m_topology(&topology) {
  m_law.build(mesh, tissues);
  m_pending.reserve(mesh.tetCount());
  m_around.reserve(4 * mesh.tetCount());
  m_pieceLimit = std::min(kLoosePiece, std::max<size_t>(8, mesh.tetCount() / 8));
  m_piece.reserve(m_pieceLimit);
  m_seen.assign(mesh.tetCount(), 0);
  m_holds.assign(mesh.tetCount(), 0);
  m_nodeTetStart.assign(mesh.nodeCount() + 1, 0);
  for (const TetIndices& tet : mesh.tets)
    for (int32_t node : tet) ++m_nodeTetStart[size_t(node) + 1];
  for (size_t i = 0; i < mesh.nodeCount(); ++i) m_nodeTetStart[i + 1] += m_nodeTetStart[i];
  m_nodeTets.resize(m_nodeTetStart.back());
  {
    std::vector<uint32_t> fill(m_nodeTetStart.begin(), m_nodeTetStart.end() - 1);
    for (size_t t = 0; t < mesh.tetCount(); ++t)
      for (int32_t node : mesh.tets[t]) m_nodeTets[fill[size_t(node)]++] = int32_t(t);
  }
  m_spikeNodes.reserve(mesh.nodeCount());
  m_surfaceFaces.assign(mesh.nodeCount(), 0);
  for (const BoundaryFace& f : topology.boundaryFaces())
    for (int32_t node : faceNodes(mesh.tets[size_t(f.tet)], f.face)) ++m_surfaceFaces[size_t(node)];
  m_boundaryFaces = topology.boundaryFaces().size();
  m_mesh = &mesh;
}

void BrainResection::reserveRecord(double duration) {
  const double rows = std::ceil(std::max(0.0, duration) * 1000.0) + 16;
  m_rows.clear();
  m_rows.reserve(size_t(rows) * recordColumns());
  m_lastRow = -1e300;
  m_droppedRows = 0;
}

bool BrainResection::act(double t, std::span<const ContactResponse> responses) {
  const bool critical = m_law.act(responses, m_pending);
  // At most a row a millisecond (within the round-off of the frame times).
  if (t >= m_lastRow + 1e-3 - 1e-9) {
    if (m_rows.size() + recordColumns() > m_rows.capacity()) {
      ++m_droppedRows;
    } else {
      const ResectionTotals& s = m_law.totals();
      double removed = 0;
      for (double v : s.removed_mm3) removed += v;
      m_rows.push_back(t);
      m_rows.push_back(removed);
      m_rows.push_back(s.bloodLoss_ml);
      m_rows.push_back(s.criticalContact_s);
      for (double v : s.removed_mm3) m_rows.push_back(v);
      m_lastRow = t;
    }
  }
  return critical;
}

void BrainResection::queue(std::span<const int32_t> tets) {
  for (int32_t t : tets)
    if (t >= 0 && size_t(t) < m_seen.size() && m_remaining.alive(t) && m_pending.size() < m_pending.capacity())
      m_pending.push_back(t);
}

RemainingMesh::Change BrainResection::removeNext() {
  if (m_pending.empty()) findLoosePieces();
  if (m_pending.empty()) return {};
  const RemainingMesh::Change change = m_remaining.remove(m_pending);
  m_pending.clear();
  m_law.removed(change.removedTets);
  // The alive tetrahedra beside this removal: where a piece may have been cut loose.
  for (const BoundaryFace& f : change.exposed)
    if (m_around.size() < m_around.capacity()) m_around.push_back(f.tet);
  // Nodes now held by one or two tetrahedra: the tip of a spike.
  for (int32_t tet : change.removedTets)
    for (int32_t node : m_mesh->tets[size_t(tet)]) {
      const uint32_t use = m_remaining.nodeUse(node);
      if (use >= 1 && use <= kSpikeUse && m_spikeNodes.size() < m_spikeNodes.capacity()) m_spikeNodes.push_back(node);
    }
  for (const BoundaryFace& f : change.takenAway)
    for (int32_t node : faceNodes(m_mesh->tets[size_t(f.tet)], f.face)) --m_surfaceFaces[size_t(node)];
  m_boundaryFaces += change.exposed.size();
  m_boundaryFaces -= change.takenAway.size();
  for (const BoundaryFace& f : change.exposed)
    for (int32_t node : faceNodes(m_mesh->tets[size_t(f.tet)], f.face)) ++m_surfaceFaces[size_t(node)];
  return change;
}

void BrainResection::findLoosePieces() {
  // From each tetrahedron beside the last removal, a flood fill across the
  // faces of alive tetrahedra: one that ends before loosePieceLimit()
  // tetrahedra is a loose piece; one that reaches as many, or a tetrahedron
  // an earlier fill of this search found holding, holds to the rest.
  // O(loosePieceLimit()) a seed at most, each tetrahedron filled once a
  // search; no allocation.
  if (m_around.empty() && m_spikeNodes.empty()) return;
  if (++m_search == 0) {  // the stamps wrapped: start them again
    std::fill(m_seen.begin(), m_seen.end(), 0);
    m_search = 1;
  }
  // A node held by one or two tetrahedra is the tip of a spike or a fin one
  // element thick: a force on it drags it through its few elements, which
  // invert. They go.
  for (int32_t node : m_spikeNodes) {
    const uint32_t use = m_remaining.nodeUse(node);
    if (use == 0 || use > kSpikeUse) continue;
    for (uint32_t i = m_nodeTetStart[size_t(node)]; i < m_nodeTetStart[size_t(node) + 1]; ++i) {
      const int32_t tet = m_nodeTets[i];
      if (!m_remaining.alive(tet) || m_seen[size_t(tet)] == m_search) continue;
      m_seen[size_t(tet)] = m_search;
      ++m_fragments;
      if (m_pending.size() < m_pending.capacity()) m_pending.push_back(tet);
    }
  }
  m_spikeNodes.clear();
  if (!m_pending.empty()) return;  // m_around is kept for the next round
  // A tetrahedron held by one face at most is a flap: a force on its free
  // node turns it about that face and inverts it. Flaps and spikes go first;
  // the next round looks at what their going exposes, and only a round with
  // neither looks for loose pieces.
  for (int32_t seed : m_around) {
    if (!m_remaining.alive(seed) || m_seen[size_t(seed)] == m_search) continue;
    int held = 0;
    for (int f = 0; f < 4; ++f) {
      const int32_t n = m_topology->neighbour(seed, f);
      held += n != kNoNeighbour && m_remaining.alive(n);
    }
    if (held > 1) continue;
    m_seen[size_t(seed)] = m_search;
    ++m_fragments;
    if (m_pending.size() < m_pending.capacity()) m_pending.push_back(seed);
  }
  if (!m_pending.empty()) return;  // m_around is kept for the next round
  for (int32_t seed : m_around) {
    if (!m_remaining.alive(seed) || m_seen[size_t(seed)] == m_search) continue;
    m_piece.clear();
    m_piece.push_back(seed);
    m_seen[size_t(seed)] = m_search;
    m_holds[size_t(seed)] = 0;
    bool holds = false;
    for (size_t i = 0; i < m_piece.size() && !holds; ++i)
      for (int f = 0; f < 4 && !holds; ++f) {
        const int32_t n = m_topology->neighbour(m_piece[i], f);
        if (n == kNoNeighbour || !m_remaining.alive(n)) continue;
        if (m_seen[size_t(n)] == m_search) {
          holds = m_holds[size_t(n)] != 0;  // reached by an earlier fill that found it holding
          continue;
        }
        if (m_piece.size() == m_pieceLimit) {
          holds = true;  // as large as a piece may be: it holds to the rest
          continue;
        }
        m_seen[size_t(n)] = m_search;
        m_holds[size_t(n)] = 0;
        m_piece.push_back(n);
      }
    if (holds) {
      for (int32_t t : m_piece) m_holds[size_t(t)] = 1;
      continue;
    }
    ++m_loosePieces;
    m_looseTets += m_piece.size();
    for (int32_t t : m_piece)
      if (m_pending.size() < m_pending.capacity()) m_pending.push_back(t);
  }
  m_around.clear();
}

}  // namespace trephine::tetra
