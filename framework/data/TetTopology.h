#pragma once
// Face adjacency of a tetrahedral mesh and what is wrong with it. Face f of
// tet t is the face opposite its node f (nodes (f+1)%4, (f+2)%4, (f+3)%4).
// A face shared by two tets links them; a face of one tet is on the boundary;
// a face claimed by three or more tets makes the mesh non-manifold.
#include <string>
#include <vector>

#include "framework/data/TetMesh.h"

namespace trephine {

inline constexpr int32_t kNoNeighbour = -1;

struct BoundaryFace {
  int32_t tet;  // the tet it belongs to
  int8_t face;  // which of its faces (opposite that local node)
};

// Problems found when the mesh is loaded: counts and the first few indices.
struct MeshReport {
  size_t invertedTets = 0;    // negative volume (node order reversed)
  size_t degenerateTets = 0;  // |volume| below the tolerance (zero volume, slivers)
  std::vector<int32_t> firstInverted, firstDegenerate;
  size_t unusedNodes = 0;
  std::vector<int32_t> firstUnused;
  size_t nonManifoldFaces = 0;            // faces shared by more than two tets
  std::vector<int32_t> firstNonManifold;  // a tet holding one
  double minVolume = 0, maxVolume = 0;    // mm^3, signed, as read
  std::string describe() const;           // one line per kind of problem, empty when clean
};

class TetTopology {
 public:
  // Builds adjacency; O(n log n) in the number of tets.
  explicit TetTopology(const TetMesh& mesh);
  TetTopology() = default;

  // The tet across face f of tet t, or kNoNeighbour.
  int32_t neighbour(int32_t tet, int face) const { return m_neighbours[size_t(tet) * 4 + face]; }
  const std::vector<BoundaryFace>& boundaryFaces() const { return m_boundary; }
  bool isBoundary(int32_t tet, int face) const { return neighbour(tet, face) == kNoNeighbour; }
  // Tets with at least one boundary face.
  bool touchesBoundary(int32_t tet) const { return m_boundaryMask[tet] != 0; }
  uint8_t boundaryMask(int32_t tet) const { return m_boundaryMask[tet]; }
  size_t nonManifoldFaces() const { return m_nonManifold; }
  int32_t firstNonManifoldTet() const { return m_firstNonManifoldTet; }

 private:
  std::vector<int32_t> m_neighbours;  // 4 per tet
  std::vector<BoundaryFace> m_boundary;
  std::vector<uint8_t> m_boundaryMask;  // bit f set: face f is on the boundary
  size_t m_nonManifold = 0;
  int32_t m_firstNonManifoldTet = -1;
};

// The nodes of face f of a tet, ordered so that their right-hand normal points
// out of a positively oriented tet.
inline std::array<int32_t, 3> faceNodes(const TetIndices& t, int f) {
  static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  return {t[kFace[f][0]], t[kFace[f][1]], t[kFace[f][2]]};
}

// Checks volumes (relative tolerance to the mean tet volume) and node use;
// non-manifold faces come from the topology.
MeshReport inspectMesh(const TetMesh& mesh, const TetTopology& topology, double degenerateFraction = 1e-6);

// Swaps two nodes of every inverted tet so all volumes are positive. Returns how many.
size_t reorient(TetMesh& mesh);

}  // namespace trephine
