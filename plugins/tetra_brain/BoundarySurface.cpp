#include "plugins/tetra_brain/BoundarySurface.h"

namespace trephine::tetra {

void BoundarySurface::build(const TetMesh& mesh, const TetTopology& topology) {
  std::vector<int32_t> vertexOf(mesh.nodeCount(), -1);
  m_mesh = {};
  m_vertexNode.clear();
  double edges = 0;
  for (const BoundaryFace& face : topology.boundaryFaces()) {
    const auto nodes = faceNodes(mesh.tets[face.tet], face.face);  // counter-clockwise seen from outside
    std::array<int32_t, 3> triangle{};
    for (int i = 0; i < 3; ++i) {
      int32_t& vertex = vertexOf[size_t(nodes[size_t(i)])];
      if (vertex < 0) {
        vertex = int32_t(m_vertexNode.size());
        m_vertexNode.push_back(nodes[size_t(i)]);
        m_mesh.vertices.push_back(mesh.nodes[size_t(nodes[size_t(i)])]);
      }
      triangle[size_t(i)] = vertex;
      edges += (mesh.nodes[size_t(nodes[size_t(i)])] - mesh.nodes[size_t(nodes[size_t((i + 1) % 3)])]).norm();
    }
    m_mesh.triangles.push_back(triangle);
  }
  m_averageEdge = m_mesh.triangles.empty() ? 0.0 : edges / (3.0 * double(m_mesh.triangles.size()));
}

void BoundarySurface::moveTo(std::span<const Vec3> nodes) {
  for (size_t v = 0; v < m_vertexNode.size(); ++v) m_mesh.vertices[v] = nodes[size_t(m_vertexNode[v])];
}

}  // namespace trephine::tetra
