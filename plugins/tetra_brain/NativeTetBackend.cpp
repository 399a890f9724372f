// NativeTetBackend: the grids of the rest shape, the frames of a deforming
// mesh, working memory and counters.
#include "plugins/tetra_brain/NativeTetBackend.h"

#include <algorithm>
#include <cmath>

#include "framework/core/Component.h"
#include "plugins/tetra_brain/cell_size/ToolQueryCost.h"

namespace trephine::tetra {

void NativeTetBackend::bind(const TetData& data) {
  m_mesh = data.mesh;
  m_topology = data.topology;
  m_options = data.options;
  m_nodes = m_mesh->nodes.data();
  m_displacementBound = m_queryGrowth = 0;
  m_drift.forget();
  m_locateWork = {};
  buildAccelerations();
}

void NativeTetBackend::buildAccelerations() {
  const TetMesh& mesh = *m_mesh;
  const size_t n = mesh.tetCount();
  m_holdsNoPoint.assign(n, 0);
  double edges = 0, volumes = 0;
  for (const TetIndices& k : mesh.tets)
    volumes += std::abs(signedVolume(mesh.nodes[k[0]], mesh.nodes[k[1]], mesh.nodes[k[2]], mesh.nodes[k[3]]));
  // As in inspectMesh: a tet a millionth of the mean volume holds no point.
  const double volumeTolerance = 1e-6 * volumes / double(n);
  for (size_t t = 0; t < n; ++t) {
    const TetIndices& k = mesh.tets[t];
    edges += (mesh.nodes[k[0]] - mesh.nodes[k[1]]).norm() + (mesh.nodes[k[2]] - mesh.nodes[k[3]]).norm();
    const double v = signedVolume(mesh.nodes[k[0]], mesh.nodes[k[1]], mesh.nodes[k[2]], mesh.nodes[k[3]]);
    m_holdsNoPoint[t] = std::abs(v) > volumeTolerance ? 0 : kDegenerateTet;
  }
  m_averageEdge = edges / (2.0 * double(n));
  // Auto margin: a quarter of the average edge. Each cell then lists about
  // (1.5 + 0.5)^3 / 1.5^3 = 2.4 times the tets of a rigid mesh (cells of half
  // an edge, boxes of about an edge); with every node moving, a frame costs 1
  // to 2.6 times the rigid one (docs/results.md). A full edge lists about 13 times.
  m_margin = !m_options.deformable              ? 0.0
             : m_options.displacementMargin > 0 ? m_options.displacementMargin
                                                : 0.25 * m_averageEdge;
  // The tool-cost rule starts at half an edge until the tools' shells are
  // known (reserveShell); a query before that is answered on these grids.
  using Rule = TetQueryOptions::CellSizeRule;
  m_modelShells.clear();
  m_modelShellKeys.clear();
  m_cellSize = m_options.cellSize > 0                     ? m_options.cellSize
               : m_options.cellSizeRule == Rule::kEdge ? m_averageEdge
                                                       : 0.5 * m_averageEdge;
  if (m_options.cellSize <= 0 && m_options.cellSizeRule == Rule::kToolCost)
    m_boxMoments = measureBoxMoments(mesh, m_margin);
  buildFaceSets();
  buildRestGrids();
  m_tetVisits.resize(n);
  // Node -> tets, compressed rows, for the thesis's refresh of the moved tetrahedra.
  m_nodeTetStart.clear();
  m_nodeTets.clear();
  m_tetMarked.clear();
  if (m_options.deformable && m_options.search != Search::kGrid && !m_options.refreshEveryBox) {
    m_nodeTetStart.assign(mesh.nodeCount() + 1, 0);
    for (const TetIndices& k : mesh.tets)
      for (int32_t i : k) ++m_nodeTetStart[i + 1];
    for (size_t i = 0; i < mesh.nodeCount(); ++i) m_nodeTetStart[i + 1] += m_nodeTetStart[i];
    m_nodeTets.resize(m_nodeTetStart.back());
    std::vector<uint32_t> next(m_nodeTetStart.begin(), m_nodeTetStart.end() - 1);
    for (size_t t = 0; t < n; ++t)
      for (int32_t i : mesh.tets[t]) m_nodeTets[next[i]++] = int32_t(t);
    m_tetMarked.assign(n, 0);
  }
}

void NativeTetBackend::buildFaceSets() {
  m_live.build(*m_mesh, *m_topology, m_followsRemovals);
  m_faceVisits.resize(m_topology->boundaryFaces().size());
}

std::optional<std::string> NativeTetBackend::followRemovals() {
  if (m_followsRemovals) return std::nullopt;
  m_followsRemovals = true;
  if (!m_mesh) return std::nullopt;  // bind() builds them
  buildFaceSets();
  return std::nullopt;
}

void NativeTetBackend::removeTets(const RemainingMesh::Change& change) {
  if (!m_followsRemovals) return;
  for (int32_t tet : change.removedTets) m_holdsNoPoint[size_t(tet)] = kRemovedTet;
  m_live.apply(change);
}

void NativeTetBackend::buildRestGrids() {
  // The grids hold the rest boxes grown by the displacement margin (0 for a rigid mesh).
  buildTetGrids(*m_mesh, faces(), m_mesh->nodes, m_margin, m_cellSize, faceCellSize(), m_restGrids);
  m_grids = &m_restGrids;
  m_tetBoxes = m_restGrids.boxes;
  m_bounds = m_restGrids.bounds;
}

void NativeTetBackend::fitCellSizeToShell(std::span<const ShellPoint> shell) {
  // A shell counts once however many components reserve it (a proxy and a
  // contact warning share their tool's).
  const std::pair<const void*, size_t> key{shell.data(), shell.size()};
  if (shell.empty() || std::find(m_modelShellKeys.begin(), m_modelShellKeys.end(), key) != m_modelShellKeys.end())
    return;
  m_modelShellKeys.push_back(key);
  std::vector<Vec3>& points = m_modelShells.emplace_back();
  for (const ShellPoint& p : shell) points.push_back(p.position);
  const double cell = optimalToolCellSize(m_boxMoments, m_modelShells, m_averageEdge,
                                         m_options.deformable ? kDeformingToolQueryWeights : kRigidToolQueryWeights);
  if (!(cell > 0) || std::abs(cell - m_cellSize) <= 1e-9 * cell) return;
  m_cellSize = cell;
  buildRestGrids();
}

Box3 NativeTetBackend::currentBox(int32_t tet) const {
  Box3 box;
  for (int32_t i : m_mesh->tets[tet]) box.extend(m_nodes[i]);
  return box;
}

void NativeTetBackend::adoptGrids(const TetGridSet& grids) {
  // Built elsewhere for this mesh and these settings (a TetGridRebuild).
  if (grids.reference.size() != m_mesh->nodeCount() || grids.margin != m_margin) return;
  m_grids = &grids;
  m_drift.forget();
  ++m_adoptedGrids;
}

void NativeTetBackend::moveNodes(const NodeFrame& frame) {
  m_nodes = frame.nodes.data();
  // The bound the queries need is from the grids' reference: the frame's own
  // (from rest) while the grids are the rest ones, else measured here.
  // A loose bound between measurements costs little: it only admits more
  // tets to the test against their current box (locatePoints).
  const double bound = m_grids == &m_restGrids ? frame.displacementBound
                                               : m_drift.update(*m_grids, frame.nodes, frame.largestMove, m_margin);
  // Queries widen by the drift beyond the margin, and each cell of widening
  // multiplies their cost (two cells: 125 times the cells to scan). Drift
  // that far is a shape the rebuilt grids could not follow: a diverging FEM
  // moves nodes by as much as the mesh is large before it is reset, and exact
  // queries then took seconds a frame. The widening is held to
  // kMostWideningCells cells of half an average edge (or the grid's cell,
  // when larger); a tetrahedron whose nodes moved farther may then be
  // missed, and the frame is counted. The cap is a distance, not a count of
  // the grid's cells: a smaller cell (cellSizeRule="tool-cost") must not
  // make the queries inexact sooner, it makes widened frames dearer.
  const double widening = std::max(0.0, bound - m_margin);
  const double mostWidening = kMostWideningCells * std::max(m_grids->tetGrid.cellSide(), 0.5 * m_averageEdge);
  if (widening > mostWidening) ++m_framesWideningCapped;
  m_queryGrowth = std::min(widening, mostWidening);
  m_displacementBound = m_margin + m_queryGrowth < bound ? m_margin + m_queryGrowth : bound;
  if (m_queryGrowth > 0) ++m_framesBeyondMargin;
  const Vec3 grow = Vec3::Constant(m_displacementBound);
  m_bounds = Box3(m_grids->bounds.min() - grow, m_grids->bounds.max() + grow);
  if (m_options.search != Search::kGrid)
    refreshBoxes(frame.movedNodes, m_options.refreshEveryBox || frame.allMoved || m_nodeTetStart.empty());
}

void NativeTetBackend::refreshBoxes(std::span<const int32_t> movedNodes, bool all) {
  // The thesis's update of the tetrahedra's boxes to the deformed shape.
  if (all) {
    for (size_t t = 0; t < m_tetBoxes.size(); ++t) m_tetBoxes[t] = currentBox(int32_t(t));
    m_refreshedBoxes += m_tetBoxes.size();
    return;
  }
  const size_t nodes = m_mesh->nodeCount();
  for (int32_t n : movedNodes) {
    if (n < 0 || size_t(n) >= nodes) continue;
    for (uint32_t e = m_nodeTetStart[n]; e < m_nodeTetStart[n + 1]; ++e) {
      const int32_t t = m_nodeTets[e];
      if (m_tetMarked[t]) continue;
      m_tetMarked[t] = 1;
      m_tetBoxes[t] = currentBox(t);
      ++m_refreshedBoxes;
    }
  }
  for (int32_t n : movedNodes) {
    if (n < 0 || size_t(n) >= nodes) continue;
    for (uint32_t e = m_nodeTetStart[n]; e < m_nodeTetStart[n + 1]; ++e) m_tetMarked[m_nodeTets[e]] = 0;
  }
}

void NativeTetBackend::reserveShell(std::span<const ShellPoint> shell) {
  // Initialisation: the grids may be rebuilt for the cell the shells call for.
  if (m_options.cellSize <= 0 && m_options.cellSizeRule == TetQueryOptions::CellSizeRule::kToolCost)
    fitCellSizeToShell(shell);
  m_candidates.resize(1 + 4 + 12);  // a tet, its 4 neighbours, their 12 others
  if (m_hits.size() < shell.size()) {
    m_hits.resize(shell.size());
    m_depths.resize(shell.size());
    m_normals.resize(shell.size());
    m_sites.resize(shell.size());
    m_hitTets.resize(shell.size());
    m_points.resize(shell.size());
    m_pointTets.resize(shell.size());
    m_insetPoints.resize(shell.size());
    m_insetTets.resize(shell.size());
    m_locator.reserve(shell.size());
  }
}

void NativeTetBackend::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"average_edge_mm", m_averageEdge});
  counters.push_back({"cell_size_mm", m_grids->tetGrid.cellSide()});
  counters.push_back({"face_cell_size_mm", m_grids->faceGrid.cellSide()});
  counters.push_back({"grid_cells", double(m_grids->tetGrid.cellCount())});
  // Memory of the tetrahedron grid: 4 bytes per entry and per cell.
  counters.push_back({"grid_entries", double(m_grids->tetGrid.entryCount())});
  counters.push_back({"max_colliding_tetrahedra", double(m_maxCollidingTets)});
  counters.push_back({"deep_fallbacks", double(m_deepFallbacks)});
  if (m_options.search == Search::kGrid && m_locateWork.queries > 0) {
    // Per shell query, on average: the terms of the tool query's cost model.
    const double q = double(m_locateWork.queries);
    counters.push_back({"locate_cells_per_query", double(m_locateWork.cells) / q});
    counters.push_back({"locate_listed_per_query", double(m_locateWork.listed) / q});
    counters.push_back({"locate_overlapping_per_query", double(m_locateWork.overlapping) / q});
    counters.push_back({"locate_point_tests_per_query", double(m_locateWork.pointTests) / q});
  }
  if (m_options.search != Search::kGrid) counters.push_back({"scanned_tetrahedra", double(m_scannedTets)});
  if (m_followsRemovals) {
    counters.push_back({"removed_tetrahedra", double(m_live.removedTets())});
    counters.push_back({"exposed_faces", double(m_live.exposedEver())});  // inside faces a removal exposed
    counters.push_back({"most_cavity_faces", double(m_live.mostExposed())});  // of those, the most on the boundary at once
  }
  if (m_options.deformable) {
    counters.push_back({"displacement_margin_mm", m_margin});
    counters.push_back({"adopted_grids", double(m_adoptedGrids)});
    counters.push_back({"drift_measurements", double(m_drift.fullMeasurements())});  // frames that visited every node
    counters.push_back({"frames_beyond_margin", double(m_framesBeyondMargin)});
    // Drift so far beyond the margin that the queries were widened by the cap only.
    counters.push_back({"frames_widening_capped", double(m_framesWideningCapped)});
    if (m_options.search != Search::kGrid) counters.push_back({"refreshed_boxes", double(m_refreshedBoxes)});
  }
}

}  // namespace trephine::tetra
