#pragma once
// The boundary faces of a mesh now, as a resection removes tetrahedra, in the
// forms the native back-end's queries read: a flag per face of every
// tetrahedron (slot tet * 4 + face), a mask per tetrahedron, the boundary
// faces around each node, and the faces a removal exposed that were inside
// the mesh at first (the cavity's walls). The back-end's face grid keeps
// listing the first boundary (those still there pass the flag); the exposed
// faces, a cavity's worth, are read as a list. So a removal costs no grid
// rebuild and a query no more than it did before, plus the cavity's faces.
//
// Node rows hold every face around a node, the boundary ones first (a count
// per node): a face that becomes boundary, or stops being, is swapped across
// that line. apply() is O(faces changed x faces around a node) and never
// allocates: everything is sized by build().
#include <cstdint>
#include <span>
#include <vector>

#include "framework/data/RemainingMesh.h"

namespace trephine::tetra {

class LiveFaces {
 public:
  // `followsRemovals`: rows and lists sized for removals; without, the
  // rows hold the boundary faces only and apply() must not be called.
  void build(const TetMesh& mesh, const TetTopology& topology, bool followsRemovals);

  static int32_t slotOf(const BoundaryFace& f) { return f.tet * 4 + f.face; }
  static BoundaryFace faceOf(int32_t slot) { return {slot / 4, int8_t(slot % 4)}; }
  bool onBoundary(const BoundaryFace& f) const { return m_onBoundary[size_t(slotOf(f))] != 0; }
  uint8_t mask(int32_t tet) const { return m_mask[size_t(tet)]; }
  // The slots of the boundary faces holding `node` now.
  std::span<const int32_t> aroundNode(int32_t node) const {
    return {m_rows.data() + m_rowStart[size_t(node)], m_live[size_t(node)]};
  }
  // Boundary faces now that were inside the mesh at first.
  std::span<const BoundaryFace> exposed() const { return m_exposed; }

  void apply(const RemainingMesh::Change& change);

  uint64_t removedTets() const { return m_removedTets; }
  uint64_t exposedEver() const { return m_exposedEver; }
  size_t mostExposed() const { return m_mostExposed; }

 private:
  void setBoundary(int32_t slot, bool boundary);

  const TetMesh* m_mesh = nullptr;
  bool m_follows = false;
  std::vector<uint8_t> m_onBoundary;  // per slot
  std::vector<uint8_t> m_mask;        // per tet, bit f: face f on the boundary
  std::vector<uint32_t> m_rowStart;   // per node (+1), into m_rows
  std::vector<int32_t> m_rows;        // slots around each node, the boundary ones first
  std::vector<uint32_t> m_live;       // per node: how many of its row are boundary
  std::vector<BoundaryFace> m_exposed;  // capacity: every slot
  std::vector<int32_t> m_exposedAt;     // per slot: its place in m_exposed, or -1
  std::vector<uint8_t> m_firstBoundary; // per slot: on the boundary at first
  uint64_t m_removedTets = 0, m_exposedEver = 0;
  size_t m_mostExposed = 0;
};

}  // namespace trephine::tetra
