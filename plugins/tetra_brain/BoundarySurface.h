#pragma once
// The boundary faces of a tetrahedral mesh as one block of triangles (for
// the mesh collision back-ends), outward, over the boundary nodes only; the
// vertices follow the node positions of each frame.
#include <span>
#include <vector>

#include "framework/data/TriangleBlocks.h"
#include "framework/data/TetMesh.h"
#include "framework/data/TetTopology.h"

namespace trephine::tetra {

class BoundarySurface final : public TriangleBlocks {
 public:
  void build(const TetMesh& mesh, const TetTopology& topology);
  // Copies the boundary nodes' positions (one per mesh node in `nodes`).
  void moveTo(std::span<const Vec3> nodes);
  size_t blockCount() const override { return 1; }
  const TriangleMesh& block(size_t) const override { return m_mesh; }
  // The mesh node of a surface vertex.
  int32_t node(int32_t vertex) const { return m_vertexNode[size_t(vertex)]; }
  double averageEdge() const { return m_averageEdge; }  // mm, at build

 private:
  TriangleMesh m_mesh;
  std::vector<int32_t> m_vertexNode;
  double m_averageEdge = 0;
};

}  // namespace trephine::tetra
