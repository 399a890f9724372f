#include "framework/data/RemainingMesh.h"

#include <sstream>

namespace trephine {

RemainingMesh::RemainingMesh(const TetMesh& mesh, const TetTopology& topology)
    : m_mesh(&mesh), m_topology(&topology), m_alive(mesh.tetCount(), kAlive), m_nodeUse(mesh.nodeCount(), 0) {
  m_aliveCount = mesh.tetCount();
  for (const TetIndices& t : mesh.tets)
    for (const int32_t node : t) ++m_nodeUse[size_t(node)];
  m_removed.reserve(mesh.tetCount());
  m_freed.reserve(mesh.nodeCount());
  m_exposed.reserve(4 * mesh.tetCount());
  m_takenAway.reserve(4 * mesh.tetCount());
}

RemainingMesh::Change RemainingMesh::remove(std::span<const int32_t> tets) {
  m_removed.clear();
  m_freed.clear();
  m_exposed.clear();
  m_takenAway.clear();
  const int32_t count = int32_t(m_alive.size());
  // First every tetrahedron of the call is marked as going (kGoing), so that
  // a face between two of them is neither exposed nor taken away.
  for (const int32_t t : tets) {
    if (t < 0 || t >= count || !alive(t)) continue;
    m_alive[size_t(t)] = kGoing;
    --m_aliveCount;
    m_removed.push_back(t);
  }
  for (const int32_t t : m_removed) {
    for (int f = 0; f < 4; ++f) {
      const int32_t n = m_topology->neighbour(t, f);
      if (n != kNoNeighbour && alive(n)) {
        // The neighbour's face towards t (the one whose neighbour is t).
        for (int g = 0; g < 4; ++g)
          if (m_topology->neighbour(n, g) == t) {
            m_exposed.push_back({n, int8_t(g)});
            break;
          }
      } else if (n == kNoNeighbour || m_alive[size_t(n)] == kGone) {
        // t's face was boundary before this call (no neighbour, or one an
        // earlier call removed).
        m_takenAway.push_back({t, int8_t(f)});
      }
    }
    for (const int32_t node : m_mesh->tets[size_t(t)])
      if (--m_nodeUse[size_t(node)] == 0) m_freed.push_back(node);
  }
  for (const int32_t t : m_removed) m_alive[size_t(t)] = kGone;
  return {m_removed, m_exposed, m_takenAway, m_freed};
}

std::string RemainingMesh::validate() const {
  std::ostringstream problems;
  size_t alive = 0;
  std::vector<uint32_t> use(m_nodeUse.size(), 0);
  for (size_t t = 0; t < m_alive.size(); ++t) {
    if (m_alive[t] != kAlive) continue;
    ++alive;
    for (const int32_t node : m_mesh->tets[t]) ++use[size_t(node)];
  }
  if (alive != m_aliveCount) problems << "alive count " << m_aliveCount << ", counted " << alive << "\n";
  for (size_t n = 0; n < use.size(); ++n)
    if (use[n] != m_nodeUse[n]) {
      problems << "node " << n << " used by " << m_nodeUse[n] << " alive tetrahedra, counted " << use[n] << "\n";
      break;
    }
  return problems.str();
}

}  // namespace trephine
