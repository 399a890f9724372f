#pragma once
// What remains of a tetrahedral mesh as its tetrahedra are removed
// (resection): which tetrahedra are alive, which faces are on the boundary
// now (a face of an alive tetrahedron whose neighbour is removed or was
// never there), and which nodes still belong to an alive tetrahedron. The
// FEM, the collision structures and the exporters follow a removal through
// what remove() returns: the tetrahedra removed, the faces it exposed (the
// removed tetrahedra's faces towards alive neighbours, now boundary), the
// boundary faces it took away (the removed tetrahedra's own) and the nodes
// left without a tetrahedron.
//
// Removal costs O(tetrahedra removed) and never allocates: the buffers are
// sized to the mesh at construction. The mesh and its topology are kept by
// reference and must outlive this object; the topology's neighbours are
// those of the whole mesh, so nothing there changes.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "framework/data/TetMesh.h"
#include "framework/data/TetTopology.h"

namespace trephine {

class RemainingMesh {
 public:
  // Every tetrahedron alive.
  RemainingMesh(const TetMesh& mesh, const TetTopology& topology);

  // What one remove() changed; its spans are valid until the next remove().
  struct Change {
    std::span<const int32_t> removedTets;       // those that were alive
    std::span<const BoundaryFace> exposed;      // faces of alive tetrahedra that became boundary
    std::span<const BoundaryFace> takenAway;    // boundary faces of the removed tetrahedra
    std::span<const int32_t> freedNodes;        // nodes of no alive tetrahedron any more
  };
  // Removes `tets` (indices out of range, repeated or already removed are
  // skipped).
  Change remove(std::span<const int32_t> tets);

  bool alive(int32_t tet) const { return m_alive[size_t(tet)] == kAlive; }
  // Face f of an alive tetrahedron whose neighbour is not alive.
  bool onBoundary(int32_t tet, int face) const {
    if (!alive(tet)) return false;
    const int32_t n = m_topology->neighbour(tet, face);
    return n == kNoNeighbour || !alive(n);
  }
  size_t aliveCount() const { return m_aliveCount; }
  // Alive tetrahedra using the node.
  uint32_t nodeUse(int32_t node) const { return m_nodeUse[size_t(node)]; }

  // Every invariant checked against a count from scratch (O(mesh)): empty
  // when they hold, else what is wrong. For tests and checks, not the loop.
  std::string validate() const;

 private:
  // Per tetrahedron: alive, removed by an earlier call, or going in this one.
  static constexpr uint8_t kGone = 0, kAlive = 1, kGoing = 2;
  const TetMesh* m_mesh;
  const TetTopology* m_topology;
  std::vector<uint8_t> m_alive;
  std::vector<uint32_t> m_nodeUse;
  size_t m_aliveCount = 0;
  // remove()'s results, reserved for the whole mesh.
  std::vector<int32_t> m_removed, m_freed;
  std::vector<BoundaryFace> m_exposed, m_takenAway;
};

}  // namespace trephine
