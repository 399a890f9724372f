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
  for (Vec3& p : m_mesh.nodes) p = d_scale.value() * p + d_translation.value();
  const MeshReport report = inspectMesh(m_mesh, TetTopology(m_mesh));
  if (report.invertedTets > 0 && d_inverted.is("refuse")) {
    context.error(d_inverted, report.describe() + "(inverted=\"reorient\" swaps two nodes of each)");
    return;
  }
  setMesh(std::move(m_mesh));
  connectChannels(context.channels());
  if (d_boxRefresh.isSet() && d_search.is("grid"))
    context.error(d_boxRefresh,
                  "boxRefresh applies to the thesis's searches (search=\"first-tetrahedron\" or "
                  "\"previous-contact\"); the grid search refreshes no boxes");
}

LevelSet TetraBrain::exactShape() const {
  if (!d_file.isScheme()) return {};
  // The mesh was placed by p_W = scale p + translation: the level set follows,
  // in world millimetres.
  return [mesh = tetPhantomShape(std::string(d_file.schemeBody())), scale = d_scale.value(),
          translation = d_translation.value()](const Vec3& p_W) { return scale * mesh((p_W - translation) / scale); };
}

void TetraBrain::connectChannels(ChannelHub& channels) {
  m_nodeForces = &channels.publish<NodeForces>(*this, kNodeForcesChannel);
  reserveNodeForces(m_nodeForceValue.forces.capacity());
}

void TetraBrain::reserveNodeForces(size_t entries) {
  // Every slot of the channel, and the value filled each frame, hold as many
  // entries as a frame can need: publishing then never allocates.
  if (entries > m_nodeForceValue.forces.capacity()) m_nodeForceValue.forces.reserve(entries);
  if (!m_nodeForces || entries == 0) return;
  NodeForces prototype;
  prototype.forces.resize(m_nodeForceValue.forces.capacity());
  m_nodeForces->reserve(prototype);
}

std::optional<std::string> TetraBrain::followDeformation(const Component& deformer, ChannelHub& channels) {
  if (m_positions) return std::string("another component already deforms ") + path();
  m_positions = channels.subscribe<NodePositions>(deformer, kNodePositionsChannel);
  // Auto margin: a quarter of the average edge. Each cell then lists about
  // (1.5 + 0.5)^3 / 1.5^3 = 2.4 times the tets of a rigid mesh (cells of half
  // an edge, boxes of about an edge); with every node moving, a frame costs 1
  // to 2.6 times the rigid one (docs/results.md). A full edge lists about 13 times.
  m_margin = d_displacementMargin.value() > 0 ? d_displacementMargin.value() : 0.25 * m_averageEdge;
  buildAccelerations();
  if (!d_search.is("grid") && d_boxRefresh.is("moved")) {
    // Node -> tets, compressed rows.
    m_nodeTetStart.assign(m_mesh.nodeCount() + 1, 0);
    for (const TetIndices& k : m_mesh.tets)
      for (int32_t i : k) ++m_nodeTetStart[i + 1];
    for (size_t n = 0; n < m_mesh.nodeCount(); ++n) m_nodeTetStart[n + 1] += m_nodeTetStart[n];
    m_nodeTets.resize(m_nodeTetStart.back());
    std::vector<uint32_t> fill(m_nodeTetStart.begin(), m_nodeTetStart.end() - 1);
    for (size_t t = 0; t < m_mesh.tetCount(); ++t)
      for (int32_t i : m_mesh.tets[t]) m_nodeTets[fill[i]++] = int32_t(t);
    m_tetMarked.assign(m_mesh.tetCount(), 0);
  }
  return std::nullopt;
}

void TetraBrain::prepare(const RunPlan&) {
  m_nodeSlot.assign(m_mesh.nodeCount(), -1);  // only read when a component takes the node forces
  if (!m_nodeForces || m_nodeForces->readerCount() == 0) m_nodeSlot.clear();
}

void TetraBrain::setMesh(TetMesh mesh) {
  m_search = d_search.is("grid")                ? Search::kGrid
             : d_search.is("first-tetrahedron") ? Search::kFirstTetrahedron
                                                : Search::kPreviousContact;
  m_algorithm2 = d_penetration.is("algorithm2");
  m_refreshEveryBox = d_boxRefresh.is("all");
  m_mesh = std::move(mesh);
  m_nodes = m_mesh.nodes.data();
  m_topology = TetTopology(m_mesh);
  m_report = inspectMesh(m_mesh, m_topology);
  m_reoriented = m_report.invertedTets > 0 ? reorient(m_mesh) : 0;
  if (m_reoriented) m_topology = TetTopology(m_mesh);  // face orientation changed
  buildAccelerations();
}

void TetraBrain::buildAccelerations() {
  const size_t n = m_mesh.tetCount();
  m_restBoxes.resize(n);
  m_degenerate.assign(n, 0);
  m_restBounds.setEmpty();
  double edges = 0, volumes = 0;
  for (const TetIndices& k : m_mesh.tets)
    volumes += std::abs(signedVolume(m_mesh.nodes[k[0]], m_mesh.nodes[k[1]], m_mesh.nodes[k[2]], m_mesh.nodes[k[3]]));
  // As in inspectMesh: a tet a millionth of the mean volume holds no point.
  const double volumeTolerance = 1e-6 * volumes / double(n);
  for (size_t t = 0; t < n; ++t) {
    const TetIndices& k = m_mesh.tets[t];
    Box3 box;
    for (int32_t i : k) box.extend(m_mesh.nodes[i]);
    m_restBoxes[t] = box;
    m_restBounds.extend(box);
    edges += (m_mesh.nodes[k[0]] - m_mesh.nodes[k[1]]).norm() + (m_mesh.nodes[k[2]] - m_mesh.nodes[k[3]]).norm();
    const double v = signedVolume(m_mesh.nodes[k[0]], m_mesh.nodes[k[1]], m_mesh.nodes[k[2]], m_mesh.nodes[k[3]]);
    m_degenerate[t] = !(std::abs(v) > volumeTolerance);
  }
  m_averageEdge = edges / (2.0 * double(n));
  // Half the average edge by default: on the Brain3 phantom it halves the
  // haptic step of the full edge (fewer candidate tets per cell) at 8x the cells.
  const double cell = d_cellSize.value() > 0 ? d_cellSize.value() : 0.5 * m_averageEdge;
  m_tetBoxes = m_restBoxes;
  m_bounds = m_restBounds;
  // The grids hold the rest boxes grown by the displacement margin (0 for a rigid mesh).
  const Vec3 grow = Vec3::Constant(m_margin);
  auto grown = [&](Box3 box) { return Box3(box.min() - grow, box.max() + grow); };
  std::vector<Box3> boxes(n);
  for (size_t t = 0; t < n; ++t) boxes[t] = grown(m_restBoxes[t]);
  m_tetGrid.build(grown(m_restBounds), cell, boxes);
  boxes.clear();
  boxes.reserve(m_topology.boundaryFaces().size());
  for (const BoundaryFace& f : m_topology.boundaryFaces()) {
    Box3 box;
    for (int32_t i : faceNodes(m_mesh.tets[f.tet], f.face)) box.extend(m_mesh.nodes[i]);
    boxes.push_back(grown(box));
  }
  m_faceGrid.build(grown(m_restBounds), m_tetGrid.cellSide(), boxes);
  m_tetVisits.resize(n);
  m_faceVisits.resize(m_topology.boundaryFaces().size());
  // Node -> boundary faces, compressed rows.
  const auto& faces = m_topology.boundaryFaces();
  m_nodeFaceStart.assign(m_mesh.nodeCount() + 1, 0);
  for (const BoundaryFace& f : faces)
    for (int32_t i : faceNodes(m_mesh.tets[f.tet], f.face)) ++m_nodeFaceStart[i + 1];
  for (size_t i = 0; i < m_mesh.nodeCount(); ++i) m_nodeFaceStart[i + 1] += m_nodeFaceStart[i];
  m_nodeFaces.resize(m_nodeFaceStart.back());
  std::vector<uint32_t> fill(m_nodeFaceStart.begin(), m_nodeFaceStart.end() - 1);
  for (size_t f = 0; f < faces.size(); ++f)
    for (int32_t i : faceNodes(m_mesh.tets[faces[f].tet], faces[f].face)) m_nodeFaces[fill[i]++] = int32_t(f);
}

Box3 TetraBrain::currentBox(int32_t tet) const {
  Box3 box;
  for (int32_t i : m_mesh.tets[tet]) box.extend(m_nodes[i]);
  return box;
}

void TetraBrain::refresh() {
  if (!m_positions || !m_positions->fetch()) return;
  const NodePositions& frame = m_positions->read();
  if (frame.positions.size() != m_mesh.nodeCount()) {
    // Not this mesh's nodes (a faulty deformation). The slot of the last good
    // shape went back to the writer with this fetch, so the rest shape it is.
    ++m_rejectedFrames;
    m_nodes = m_mesh.nodes.data();
    m_displacementBound = m_queryGrowth = 0;
    m_bounds = m_restBounds;
    if (m_search != Search::kGrid) m_tetBoxes = m_restBoxes;  // same size: no allocation
    return;
  }
  const bool skipped = frame.step != m_lastStep + 1;  // a step in between was not seen: its moves are unknown
  m_lastStep = frame.step;
  m_nodes = frame.positions.data();
  ++m_deformationFrames;
  m_displacementBound = frame.displacementBound;
  m_largestBound = std::max(m_largestBound, m_displacementBound);
  m_queryGrowth = std::max(0.0, m_displacementBound - m_margin);
  if (m_queryGrowth > 0) ++m_framesBeyondMargin;
  const Vec3 grow = Vec3::Constant(m_displacementBound);
  m_bounds = Box3(m_restBounds.min() - grow, m_restBounds.max() + grow);
  if (m_search != Search::kGrid) refreshBoxes(frame, m_refreshEveryBox || frame.allMoved || skipped);
}

void TetraBrain::refreshBoxes(const NodePositions& frame, bool all) {
  // The thesis's update of the tetrahedra's boxes to the deformed shape.
  if (all) {
    for (size_t t = 0; t < m_tetBoxes.size(); ++t) m_tetBoxes[t] = currentBox(int32_t(t));
    m_refreshedBoxes += m_tetBoxes.size();
    return;
  }
  for (int32_t n : frame.movedNodes) {
    if (n < 0 || size_t(n) >= m_mesh.nodeCount()) continue;
    for (uint32_t e = m_nodeTetStart[n]; e < m_nodeTetStart[n + 1]; ++e) {
      const int32_t t = m_nodeTets[e];
      if (m_tetMarked[t]) continue;
      m_tetMarked[t] = 1;
      m_tetBoxes[t] = currentBox(t);
      ++m_refreshedBoxes;
    }
  }
  for (int32_t n : frame.movedNodes) {
    if (n < 0 || size_t(n) >= m_mesh.nodeCount()) continue;
    for (uint32_t e = m_nodeTetStart[n]; e < m_nodeTetStart[n + 1]; ++e) m_tetMarked[m_nodeTets[e]] = 0;
  }
}

void TetraBrain::reserveShell(std::span<const ShellPoint> shell) {
  m_candidates.resize(1 + 4 + 12);  // a tet, its 4 neighbours, their 12 others
  if (m_nodeForceValue.forces.capacity() < 4 * shell.size()) reserveNodeForces(4 * shell.size());
  if (std::find(m_shells.begin(), m_shells.end(), shell.data()) == m_shells.end()) m_shells.push_back(shell.data());
  if (m_hits.size() < shell.size()) {
    m_hits.resize(shell.size());
    m_depths.resize(shell.size());
    m_normals.resize(shell.size());
    m_points.resize(shell.size());
    m_pointTets.resize(shell.size());
    m_insetPoints.resize(shell.size());
    m_insetTets.resize(shell.size());
    m_locator.reserve(shell.size());
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
  // Memory of the tetrahedron grid: 4 bytes per entry and per cell.
  counters.push_back({"grid_entries", double(m_tetGrid.entryCount())});
  counters.push_back({"contact_frames", double(m_contactFrames)});
  counters.push_back({"max_colliding_tetrahedra", double(m_maxCollidingTets)});
  counters.push_back({"deep_fallbacks", double(m_deepFallbacks)});
  if (!d_search.is("grid")) counters.push_back({"scanned_tetrahedra", double(m_scannedTets)});
  if (m_positions) {
    counters.push_back({"deformation_frames", double(m_deformationFrames)});
    counters.push_back({"displacement_margin_mm", m_margin});
    counters.push_back({"largest_displacement_bound_mm", m_largestBound});
    counters.push_back({"frames_beyond_margin", double(m_framesBeyondMargin)});
    if (m_rejectedFrames) counters.push_back({"rejected_position_frames", double(m_rejectedFrames)});
    if (!d_search.is("grid")) counters.push_back({"refreshed_boxes", double(m_refreshedBoxes)});
  }
  if (m_unreservedShellCalls) counters.push_back({"unreserved_shell_calls", double(m_unreservedShellCalls)});
}

}  // namespace trephine::tetra
