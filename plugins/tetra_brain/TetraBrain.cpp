#include "plugins/tetra_brain/TetraBrain.h"

#include <algorithm>
#include <cmath>

#include "framework/core/Lifecycle.h"
#include "plugins/tetra_brain/TetPhantoms.h"
#include "plugins/tetra_brain/io/TetMeshReader.h"

namespace trephine::tetra {

void TetraBrain::init(InitContext& context) {
  try {
    m_mesh = d_file.isScheme() ? makeTetPhantom(std::string(d_file.schemeBody())) : readTetMesh(d_file.path());
  } catch (const std::exception& e) {
    context.error(d_file, e.what());
    return;
  }
  if (m_mesh.tetCount() == 0) {
    context.error(d_file, "the mesh has no tetrahedra");
    return;
  }
  for (Vec3& p : m_mesh.nodes) p += d_translation.value();
  const MeshReport report = inspectMesh(m_mesh, TetTopology(m_mesh));
  if (report.invertedTets > 0 && d_inverted.is("refuse")) {
    context.error(d_inverted, report.describe() + "(inverted=\"reorient\" swaps two nodes of each)");
    return;
  }
  setMesh(std::move(m_mesh));
}

void TetraBrain::setMesh(TetMesh mesh) {
  m_mesh = std::move(mesh);
  m_topology = TetTopology(m_mesh);
  m_report = inspectMesh(m_mesh, m_topology);
  m_reoriented = m_report.invertedTets > 0 ? reorient(m_mesh) : 0;
  if (m_reoriented) m_topology = TetTopology(m_mesh);  // face orientation changed
  buildAccelerations();
}

void TetraBrain::buildAccelerations() {
  const size_t n = m_mesh.tetCount();
  m_tetBoxes.resize(n);
  m_degenerate.assign(n, 0);
  m_bounds.setEmpty();
  double edges = 0, volumes = 0;
  for (const TetIndices& k : m_mesh.tets)
    volumes += std::abs(signedVolume(m_mesh.nodes[k[0]], m_mesh.nodes[k[1]], m_mesh.nodes[k[2]], m_mesh.nodes[k[3]]));
  // As in inspectMesh: a tet a millionth of the mean volume holds no point.
  const double volumeTolerance = 1e-6 * volumes / double(n);
  for (size_t t = 0; t < n; ++t) {
    const TetIndices& k = m_mesh.tets[t];
    Box3 box;
    for (int32_t i : k) box.extend(m_mesh.nodes[i]);
    m_tetBoxes[t] = box;
    m_bounds.extend(box);
    edges += (m_mesh.nodes[k[0]] - m_mesh.nodes[k[1]]).norm() + (m_mesh.nodes[k[2]] - m_mesh.nodes[k[3]]).norm();
    const double v = signedVolume(m_mesh.nodes[k[0]], m_mesh.nodes[k[1]], m_mesh.nodes[k[2]], m_mesh.nodes[k[3]]);
    m_degenerate[t] = !(std::abs(v) > volumeTolerance);
  }
  m_averageEdge = edges / (2.0 * double(n));
  // Half the average edge by default: on the Brain3 phantom it halves the
  // haptic step of the full edge (fewer candidate tets per cell) at 8x the cells.
  const double cell = d_cellSize.value() > 0 ? d_cellSize.value() : 0.5 * m_averageEdge;
  m_tetGrid.build(m_bounds, cell, m_tetBoxes);
  std::vector<Box3> faceBoxes;
  faceBoxes.reserve(m_topology.boundaryFaces().size());
  for (const BoundaryFace& f : m_topology.boundaryFaces()) {
    Box3 box;
    for (int32_t i : faceNodes(m_mesh.tets[f.tet], f.face)) box.extend(m_mesh.nodes[i]);
    faceBoxes.push_back(box);
  }
  m_faceGrid.build(m_bounds, m_tetGrid.cellSide(), faceBoxes);
}

void TetraBrain::reserveShell(std::span<const ShellPoint> shell) {
  m_candidates.resize(1 + 4 + 12);  // a tet, its 4 neighbours, their 12 others
  if (std::find(m_shells.begin(), m_shells.end(), shell.data()) == m_shells.end()) m_shells.push_back(shell.data());
  if (m_hits.size() < shell.size()) {
    m_hits.resize(shell.size());
    m_depths.resize(shell.size());
    m_normals.resize(shell.size());
    m_points.resize(shell.size());
  }
}

void TetraBrain::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"nodes", double(m_mesh.nodeCount())});
  counters.push_back({"tetrahedra", double(m_mesh.tetCount())});
  counters.push_back({"boundary_faces", double(m_topology.boundaryFaces().size())});
  counters.push_back({"reoriented_tetrahedra", double(m_reoriented)});
  counters.push_back({"degenerate_tetrahedra", double(m_report.degenerateTets)});
  counters.push_back({"unused_nodes", double(m_report.unusedNodes)});
  counters.push_back({"non_manifold_faces", double(m_report.nonManifoldFaces)});
  counters.push_back({"average_edge_mm", m_averageEdge});
  counters.push_back({"cell_size_mm", m_tetGrid.cellSide()});
  counters.push_back({"grid_cells", double(m_tetGrid.cellCount())});
  counters.push_back({"contact_frames", double(m_contactFrames)});
  counters.push_back({"max_colliding_tetrahedra", double(m_maxCollidingTets)});
  counters.push_back({"deep_fallbacks", double(m_deepFallbacks)});
  if (!d_search.is("grid")) counters.push_back({"scanned_tetrahedra", double(m_scannedTets)});
  if (m_unreservedShellCalls) counters.push_back({"unreserved_shell_calls", double(m_unreservedShellCalls)});
}

}  // namespace trephine::tetra
