#include "plugins/tetra_brain/TetraBrain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "framework/geometry/BackendBinding.h"
#include "framework/core/Lifecycle.h"
#include "framework/logs/EventLog.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "plugins/tetra_brain/TetPhantoms.h"
#include "framework/formats/mesh/TetMeshReader.h"
#include "framework/formats/mesh/VtuWriter.h"

namespace trephine::tetra {

void TetraBrain::init(InitContext& context) {
  // The collision back-end first: an unknown one is reported with any error of the mesh.
  m_backend = createBackendAt<TetBackend>(context, d_backend, kTypeName);
  checkNativeOnlyFields(context);
  if (!d_saveDeformed.value().empty() && !formats::isWritableTetMeshName(d_saveDeformed.value()))
    context.error(d_saveDeformed, "expected a mesh file name ending in .vtu, .mesh or .mesh.gz");
  try {
    m_mesh = d_file.isScheme() ? makeTetPhantom(std::string(d_file.schemeBody())) : formats::readTetMesh(d_file.path());
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
  if (report.unusedNodes > 0) warnUnusedNodes(context, report);
  if (report.invertedTets > 0 && d_inverted.is("refuse")) {
    context.error(d_inverted, report.describe() + "(inverted=\"reorient\" swaps two nodes of each)");
    return;
  }
  if (!m_backend) return;
  try {
    setMesh(std::move(m_mesh));
  } catch (const std::exception& e) {  // the back-end could not take the mesh
    context.error(d_backend, e.what());
    m_bound = false;
    return;
  }
  connectChannels(context.channels());
  if (d_cellSize.isSet() && d_cellSizeRule.isSet())
    context.error(d_cellSizeRule, "has no effect when cellSize is given (it picks the cell size when cellSize is not)");
  if (d_boxRefresh.isSet() && d_search.is("grid"))
    context.error(d_boxRefresh,
                  "boxRefresh applies to the thesis's searches (search=\"first-tetrahedron\" or "
                  "\"previous-contact\"); the grid search refreshes no boxes");
}

void TetraBrain::warnUnusedNodes(InitContext& context, const MeshReport& report) const {
  // A node no tetrahedron holds is no part of the body: it neither collides
  // nor deforms. Usually a stray vertex of an export (a point at the origin,
  // or far away) that the author did not mean to keep: name it, where it is.
  std::ostringstream s;
  s << report.unusedNodes << (report.unusedNodes == 1 ? " node is" : " nodes are")
    << " used by no tetrahedron and ignored:";
  for (size_t i = 0; i < report.firstUnused.size(); ++i) {
    const Vec3& p = m_mesh.nodes[size_t(report.firstUnused[i])];
    s << (i ? "," : "") << " node " << report.firstUnused[i] << " (counted from 0) at (" << p.x() << ", " << p.y()
      << ", " << p.z() << ") mm";
  }
  if (report.unusedNodes > report.firstUnused.size()) s << ", ...";
  context.warning(d_file, s.str());
}

void TetraBrain::checkNativeOnlyFields(InitContext& context) {
  // The thesis's options shape the native back-end's grids and searches; a
  // mesh back-end would silently ignore them: refuse them.
  if (d_backend.value() == "native") return;
  const BaseField* nativeFields[] = {&d_cellSize,           &d_cellSizeRule, &d_search,
                                     &d_penetration,        &d_displacementMargin, &d_boxRefresh};
  for (const BaseField* field : nativeFields)
    if (field->isSet())
      context.error(*field, "applies to backend=\"native\" only (backend=\"" + d_backend.value() + "\" ignores it)");
}

TetQueryOptions TetraBrain::queryOptions() const {
  TetQueryOptions options;
  options.search = d_search.is("grid")                ? TetQueryOptions::Search::kGrid
                   : d_search.is("first-tetrahedron") ? TetQueryOptions::Search::kFirstTetrahedron
                                                      : TetQueryOptions::Search::kPreviousContact;
  options.algorithm2 = d_penetration.is("algorithm2");
  options.refreshEveryBox = d_boxRefresh.is("all");
  options.cellSize = d_cellSize.value();
  options.cellSizeRule = d_cellSizeRule.is("tool-cost")   ? TetQueryOptions::CellSizeRule::kToolCost
                         : d_cellSizeRule.is("half-edge") ? TetQueryOptions::CellSizeRule::kHalfEdge
                                                          : TetQueryOptions::CellSizeRule::kEdge;
  options.displacementMargin = d_displacementMargin.value();
  options.contactDepth = d_contactDepth.value();
  options.deformable = m_positions.has_value();
  return options;
}

double TetraBrain::resolution() const {
  std::vector<double> edges;
  edges.reserve(6 * m_mesh.tets.size());
  for (const TetIndices& t : m_mesh.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) edges.push_back((m_mesh.nodes[size_t(t[a])] - m_mesh.nodes[size_t(t[b])]).norm());
  if (edges.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(edges.begin(), edges.begin() + edges.size() / 2, edges.end());
  return edges[edges.size() / 2];
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
  m_deformer = &deformer;
  if (m_bound) bindBackend();  // the grids are grown by the displacement margin
  return std::nullopt;
}

std::optional<std::string> TetraBrain::declareTissue(const TissueSpec& tissue) {
  if (m_mesh.tetCount() == 0) return std::nullopt;  // the mesh did not load: its own error says why
  return m_tissues.declare(tissue, m_mesh.labels);
}

std::optional<std::string> TetraBrain::enableResection(EventLog& events) {
  if (m_resection) return std::string("another Resection already resects ") + path();
  if (!m_bound) return std::nullopt;  // the mesh or the back-end did not load: their own errors say why
  if (auto why = m_backend->followRemovals())
    return "backend=\"" + d_backend.value() + "\" " + *why + ": resection needs backend=\"native\"";
  m_resection = std::make_unique<BrainResection>(m_mesh, m_topology, m_tissues);
  m_events = &events;
  return std::nullopt;
}

TetraBrain::PlacedRegion TetraBrain::labelBall(const Vec3& centre, double radius, int32_t label) {
  PlacedRegion placed;
  if (!m_tissues.empty() || m_deformer || m_resection) {
    placed.error = "the labels of " + path() +
                   " were read already: place this before the brain's Tissue, Resection and deformation components";
    return placed;
  }
  for (int32_t l : m_mesh.labels)
    if (l == label) {
      placed.error = "label " + std::to_string(label) + " is in use in " + path() + ": give the tumour a label of its own";
      placed.atLabel = true;
      return placed;
    }
  std::vector<size_t> inside;
  for (size_t t = 0; t < m_mesh.tetCount(); ++t) {
    Vec3 c = Vec3::Zero();
    for (int32_t n : m_mesh.tets[t]) c += m_mesh.nodes[size_t(n)];
    if ((c / 4 - centre).norm() < radius) inside.push_back(t);
  }
  if (inside.empty()) {
    placed.error = "no tetrahedron of " + path() + " has its centre within " + std::to_string(radius) +
                   " mm of (" + std::to_string(centre.x()) + ", " + std::to_string(centre.y()) + ", " +
                   std::to_string(centre.z()) + ") mm: the tumour lies outside the brain";
    return placed;
  }
  if (m_mesh.labels.empty()) m_mesh.labels.assign(m_mesh.tetCount(), 1);  // the rest: label 1
  for (size_t t : inside) {
    m_mesh.labels[t] = label;
    const auto& k = m_mesh.tets[t];
    placed.volume +=
        std::abs(signedVolume(m_mesh.nodes[size_t(k[0])], m_mesh.nodes[size_t(k[1])], m_mesh.nodes[size_t(k[2])],
                              m_mesh.nodes[size_t(k[3])]));
  }
  placed.tets = inside.size();
  return placed;
}

ChangeQueue<int32_t>& TetraBrain::subscribeRemovals() {
  m_removalReaders.push_back(std::make_unique<ChangeQueue<int32_t>>(std::max<size_t>(m_mesh.tetCount(), 1)));
  return *m_removalReaders.back();
}

int TetraBrain::applyRemovals(double t) {
  // The tetrahedra due to go, then the pieces they cut loose: each change
  // reaches the back-end and every reader before the next is made.
  int removed = 0;
  for (RemainingMesh::Change change = m_resection->removeNext(); !change.removedTets.empty();
       change = m_resection->removeNext()) {
    askBackend(*this, d_backend, [&] { m_backend->removeTets(change); });
    for (auto& reader : m_removalReaders)
      for (int32_t tet : change.removedTets) reader->push(tet);
    removed += int(change.removedTets.size());
  }
  if (removed > 0 && m_resection->remaining().aliveCount() == 0 && m_events)
    m_events->log(t, "brain_resected_entirely", "no tetrahedron of the brain remains", this);
  return removed;
}

std::optional<std::string> TetraBrain::followGridRebuild(const Component& rebuilder, ChannelHub& channels) {
  if (m_grids) return std::string("another component already rebuilds the grids of ") + path();
  m_grids = channels.subscribe<TetGridSet>(rebuilder, kGridsChannelName);
  return std::nullopt;
}

void TetraBrain::prepare(const RunPlan& plan) {
  if (m_resection) m_resection->reserveRecord(plan.duration);
  m_nodeSlot.assign(m_mesh.nodeCount(), -1);  // only read when a component takes the node forces
  if (!m_nodeForces || m_nodeForces->readerCount() == 0) m_nodeSlot.clear();
  if (!m_nodeSlot.empty() && d_forceSpread.value() > 0) buildForceSpread();
}

void TetraBrain::buildForceSpread() {
  // Boundary nodes sorted by x: each node's neighbours within R are found in
  // an x window. Weights (1 - (d / R)^2)^2, normalised per node, so each
  // share keeps its sum; a node with no boundary node within R keeps its own.
  const double R = d_forceSpread.value();
  // A resected brain's surface moves inwards as tissue goes: every node may
  // come to the surface, and those on it when a force is shared are chosen
  // then (publishNodeForces).
  std::vector<int32_t> boundary;
  std::vector<char> onBoundary(m_mesh.nodeCount(), m_resection ? 1 : 0);
  for (const BoundaryFace& f : m_topology.boundaryFaces())
    for (int32_t n : faceNodes(m_mesh.tets[f.tet], f.face)) onBoundary[n] = 1;
  for (size_t n = 0; n < onBoundary.size(); ++n)
    if (onBoundary[n]) boundary.push_back(int32_t(n));
  std::sort(boundary.begin(), boundary.end(),
            [&](int32_t a, int32_t b) { return m_mesh.nodes[a].x() < m_mesh.nodes[b].x(); });
  m_spreadStart.assign(1, 0);
  m_spreadNodes.clear();
  m_spreadWeights.clear();
  size_t widest = 1;
  for (size_t n = 0; n < m_mesh.nodeCount(); ++n) {
    const Vec3& p = m_mesh.nodes[n];
    const size_t rowStart = m_spreadNodes.size();
    double total = 0;
    auto it = std::lower_bound(boundary.begin(), boundary.end(), p.x() - R,
                               [&](int32_t b, double x) { return m_mesh.nodes[b].x() < x; });
    for (; it != boundary.end() && m_mesh.nodes[*it].x() <= p.x() + R; ++it) {
      const double d2 = (m_mesh.nodes[*it] - p).squaredNorm() / (R * R);
      if (d2 >= 1) continue;
      const double w = (1 - d2) * (1 - d2);
      m_spreadNodes.push_back(*it);
      m_spreadWeights.push_back(w);
      total += w;
    }
    if (total == 0) {
      m_spreadNodes.push_back(int32_t(n));
      m_spreadWeights.push_back(1.0);
      total = 1;
    }
    for (size_t k = rowStart; k < m_spreadNodes.size(); ++k) m_spreadWeights[k] /= total;
    widest = std::max(widest, m_spreadNodes.size() - rowStart);
    m_spreadStart.push_back(uint32_t(m_spreadNodes.size()));
  }
  // The spread forces touch at most every node, or each pressed node's row.
  const size_t entries = std::min(m_mesh.nodeCount(), m_nodeForceValue.forces.capacity() * widest);
  m_spreadValue.forces.reserve(entries);
  reserveNodeForces(std::max(entries, m_nodeForceValue.forces.capacity()));
}

void TetraBrain::setMesh(TetMesh mesh) {
  m_mesh = std::move(mesh);
  m_nodes = m_mesh.nodes.data();
  m_topology = TetTopology(m_mesh);
  m_report = inspectMesh(m_mesh, m_topology);
  m_reoriented = m_report.invertedTets > 0 ? reorient(m_mesh) : 0;
  if (m_reoriented) m_topology = TetTopology(m_mesh);  // face orientation changed
  m_restBounds.setEmpty();
  for (const Vec3& p : m_mesh.nodes) m_restBounds.extend(p);
  m_bounds = m_restBounds;
  if (!m_backend) m_backend = std::make_unique<NativeTetBackend>();
  m_bound = false;
  bindBackend();
}

void TetraBrain::bindBackend() {
  m_backend->bind({&m_mesh, &m_topology, queryOptions()});
  m_bound = true;
}

TargetFrame TetraBrain::beginFrame(double t) {
  takeLatestShape();
  // The tetrahedra the last frame's tools took go now: every tool of this
  // frame sees the mesh without them.
  const int removed = m_resection ? applyRemovals(t) : 0;
  return {m_shapeFailures, removed};
}

void TetraBrain::takeLatestShape() {
  if (!m_bound || !m_positions) return;
  // New grids (built off this thread) are read in place: adopting them is a pointer.
  const bool newGrids = m_grids && m_grids->fetch();
  if (newGrids) askBackend(*this, d_backend, [&] { m_backend->adoptGrids(m_grids->read()); });
  const bool newShape = m_positions->fetch();
  if (!newShape && !(newGrids && m_deformationFrames > 0)) return;
  const NodePositions& frame = m_positions->read();
  if (frame.positions.size() != m_mesh.nodeCount()) {
    // Not this mesh's nodes (a faulty deformation). The slot of the last good
    // shape went back to the writer with this fetch, so the rest shape it is.
    if (newShape) {
      ++m_rejectedFrames;
      ++m_shapeFailures;
    }
    m_nodes = m_mesh.nodes.data();
    m_bounds = m_restBounds;
    askBackend(*this, d_backend, [&] { m_backend->moveNodes({m_mesh.nodes, 0.0, {}, true}); });
    return;
  }
  // A step in between was not seen (its moves are unknown), or only the grids are new: all moved.
  const bool skipped = !newShape || frame.step != m_lastStep + 1;
  if (newShape) {
    m_lastStep = frame.step;
    ++m_deformationFrames;
    if (frame.resets != m_deformationResets) {
      ++m_shapeFailures;
      m_deformationResets = frame.resets;
    }
  }
  m_nodes = frame.positions.data();
  m_largestBound = std::max(m_largestBound, frame.displacementBound);
  const Vec3 grow = Vec3::Constant(frame.displacementBound);
  m_bounds = Box3(m_restBounds.min() - grow, m_restBounds.max() + grow);
  askBackend(*this, d_backend, [&] {
    m_backend->moveNodes({frame.positions, frame.displacementBound, frame.movedNodes, frame.allMoved || skipped,
                          skipped ? INFINITY : frame.largestMove});
  });
}

ContactMemory TetraBrain::reserveShell(std::span<const ShellPoint> shell) {
  ContactMemory memory;
  if (!m_bound) return memory;
  m_backend->reserveShell(shell);
  // The tool's sites may take the back-end's largest contact, and the node
  // forces the sites of every tool at once.
  memory.sites.reserve(m_backend->siteCapacity());
  memory.touched.reserve(m_backend->siteCapacity());  // the tetrahedra a contact touches (resection)
  m_reservedSites += memory.sites.capacity();
  if (m_nodeForceValue.forces.capacity() < 4 * m_reservedSites) reserveNodeForces(4 * m_reservedSites);
  return memory;
}

void TetraBrain::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
  if (m_bound) m_backend->describeTool(shell, solid);
}

// The queries go to the collision back-end once it is bound to the mesh.
// Before that (the mesh or the back-end failed to load, and the tools' init
// still announces their shells) there is nothing to hit.
ShellContact TetraBrain::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool, ContactMemory& memory) {
  if (!m_bound) return {};
  ++m_queries;
  const bool wantSites = !m_nodeSlot.empty();
  const TetContact result =
      askBackend(*this, d_backend, [&] { return m_backend->collide(X_WT, shell, wantSites, memory.searchStart); });
  if (result.contact.points > 0) ++m_contactFrames;
  // Copied into the tool's memory: the back-end's span lasts only until its
  // next query, which may be another tool's.
  const size_t kept = std::min(result.sites.size(), memory.sites.capacity());
  memory.sites.assign(result.sites.begin(), result.sites.begin() + kept);
  ShellContact contact = result.contact;
  contact.sites = memory.sites;
  if (m_resection) {
    // What the removal law reads in the response: the tetrahedra touched.
    memory.touched.clear();
    for (int32_t tet : result.tets)
      if (memory.touched.size() < memory.touched.capacity()) memory.touched.push_back(tet);
    contact.touched = memory.touched;
  }
  return contact;
}

std::optional<size_t> TetraBrain::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  if (!m_bound) return std::nullopt;
  ++m_queries;
  return askBackend(*this, d_backend, [&] { return m_backend->broadPhase(X_WT, shell); });
}
SweepResult TetraBrain::sweep(const SweepQuery& query) const {
  ++m_queries;
  return m_bound ? askBackend(*this, d_backend, [&] { return m_backend->sweep(query); }) : SweepResult{};
}
bool TetraBrain::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  ++m_queries;
  return m_bound && askBackend(*this, d_backend, [&] { return m_backend->overlaps(X_WT, shell); });
}
std::optional<SurfaceHit> TetraBrain::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  return m_bound ? askBackend(*this, d_backend, [&] { return m_backend->raycast(origin, direction, maxDistance); })
                 : std::nullopt;
}

void TetraBrain::respond(double t, std::span<const ContactResponse> responses) {
  if (m_resection) {
    const uint64_t stretches = m_resection->totals().criticalContacts;
    m_resection->act(t, responses);
    if (m_resection->totals().criticalContacts > stretches && m_events)
      m_events->log(t, "critical_tissue_contact", "a tool touches tissue declared critical", this);
  }
  if (m_nodeSlot.empty()) return;  // no component reads the node forces
  publishNodeForces(t, responses);
}

namespace {
bool pushes(const ContactResponse& response) {
  return !response.sites.empty() && response.forceOnTarget_N.allFinite() && !response.forceOnTarget_N.isZero(0.0);
}
}  // namespace

void TetraBrain::publishNodeForces(double t, std::span<const ContactResponse> responses) {
  // The reaction on the mesh: each tool's force shared among its contact's
  // sites by depth (the points that press hardest carry most), then among
  // each site's nodes by its weights, so that the nodal forces sum to the
  // contact forces and act where they act. The responses come in the contact
  // frame's order (the renderers' paths), so the sums are the same whatever
  // order the tools are listed in; one value a frame.
  size_t siteCount = 0, pressing = 0;
  for (const ContactResponse& response : responses) {
    if (!pushes(response)) continue;
    ++pressing;
    siteCount += response.sites.size();
  }
  if (pressing == 0) {
    // No contact: the reader's last forces must end too (published once).
    if (m_nodeForceValue.forces.empty()) return;
    m_nodeForceValue.forces.clear();
    m_nodeForceValue.t = t;
    m_nodeForceValue.resetsSeen = m_deformationResets;
    m_nodeForces->publish(m_nodeForceValue);
    return;
  }
  std::vector<NodeForce>& forces = m_nodeForceValue.forces;
  // Within the capacity reserveShell() gave it: no allocation.
  forces.resize(std::min(4 * siteCount, forces.capacity()));
  uint32_t count = 0;
  for (const ContactResponse& response : responses) {
    if (!pushes(response)) continue;
    const std::span<const ContactSite> sites = response.sites;
    const Vec3& forceOnTarget_N = response.forceOnTarget_N;
    double depthSum = 0;
    for (const ContactSite& site : sites) depthSum += site.depth;
    for (const ContactSite& site : sites) {
      const double share = depthSum > 0 ? site.depth / depthSum : 1.0 / double(sites.size());
      if (share == 0) continue;
      for (int i = 0; i < 4; ++i) {
        if (site.nodes[i] < 0 || site.weights[i] == 0) continue;
        int32_t& slot = m_nodeSlot[site.nodes[i]];
        if (slot < 0) {
          if (count == forces.size()) continue;  // cannot happen: the capacity covers every site's nodes
          slot = int32_t(count++);
          forces[slot] = {site.nodes[i], Vec3::Zero()};
        }
        forces[slot].force += (share * site.weights[i]) * forceOnTarget_N;
      }
    }
  }
  forces.resize(count);
  for (const NodeForce& f : forces) m_nodeSlot[f.node] = -1;
  m_nodeForceValue.t = t;
  m_nodeForceValue.resetsSeen = m_deformationResets;
  if (m_spreadStart.empty()) {
    m_largestNodeForceCount = std::max<uint64_t>(m_largestNodeForceCount, forces.size());
    m_nodeForces->publish(m_nodeForceValue);
    return;
  }
  // forceSpread: each node's force shared among its boundary neighbours.
  // Appended within the capacity reserved in prepare(): no allocation, and
  // only the entries in use are written.
  std::vector<NodeForce>& spread = m_spreadValue.forces;
  spread.clear();
  auto shareTo = [&](int32_t node, const Vec3& force) {
    int32_t& slot = m_nodeSlot[node];
    if (slot < 0) {
      if (spread.size() == spread.capacity()) return;  // cannot happen: the capacity covers every node touched
      slot = int32_t(spread.size());
      spread.push_back({node, Vec3::Zero()});
    }
    spread[slot].force += force;
  };
  for (const NodeForce& f : forces) {
    // On a resected brain, among the row's nodes on the surface now, their
    // weights renormalised; none there: the node keeps its force.
    double weight = 1;
    if (m_resection) {
      weight = 0;
      for (uint32_t e = m_spreadStart[f.node]; e < m_spreadStart[f.node + 1]; ++e)
        if (m_resection->onSurface(m_spreadNodes[e])) weight += m_spreadWeights[e];
      if (!(weight > 0)) {
        shareTo(f.node, f.force);
        continue;
      }
    }
    for (uint32_t e = m_spreadStart[f.node]; e < m_spreadStart[f.node + 1]; ++e)
      if (!m_resection || m_resection->onSurface(m_spreadNodes[e]))
        shareTo(m_spreadNodes[e], (m_spreadWeights[e] / weight) * f.force);
  }
  for (const NodeForce& f : spread) m_nodeSlot[f.node] = -1;
  m_spreadValue.t = t;
  m_spreadValue.resetsSeen = m_deformationResets;
  m_largestNodeForceCount = std::max<uint64_t>(m_largestNodeForceCount, spread.size());
  m_nodeForces->publish(m_spreadValue);
}

void TetraBrain::declareOutputs(std::vector<OutputFile>& outputs) const {
  if (!d_saveDeformed.value().empty()) outputs.push_back({d_saveDeformed.value(), &d_saveDeformed});
}

void TetraBrain::finish(FinishContext& context) {
  if (d_saveDeformed.value().empty() || context.outputDirectory().empty() || !m_bound) return;
  if (!context.claimOutput(*this, d_saveDeformed.value())) return;
  takeLatestShape();  // the deformation's last shape, also when no tool asked for it during the run
  TetMesh deformed;
  if (m_resection) {
    // What remains: its tetrahedra with their labels, on the nodes they use.
    const RemainingMesh& left = m_resection->remaining();
    std::vector<int32_t> renumbered(m_mesh.nodeCount(), -1);
    for (size_t t = 0; t < m_mesh.tetCount(); ++t) {
      if (!left.alive(int32_t(t))) continue;
      TetIndices tet = m_mesh.tets[t];
      for (int32_t& node : tet) {
        if (renumbered[size_t(node)] < 0) {
          renumbered[size_t(node)] = int32_t(deformed.nodes.size());
          deformed.nodes.push_back(m_nodes[node]);
        }
        node = renumbered[size_t(node)];
      }
      deformed.tets.push_back(tet);
      if (!m_mesh.labels.empty()) deformed.labels.push_back(m_mesh.labels[t]);
    }
  } else {
    deformed.nodes.assign(m_nodes, m_nodes + m_mesh.nodeCount());
    deformed.tets = m_mesh.tets;
    deformed.labels = m_mesh.labels;
  }
  try {
    formats::writeTetMeshFile(deformed, context.outputDirectory() / d_saveDeformed.value());
  } catch (const std::exception& e) {
    context.error(*this, e.what());
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
  counters.push_back({"contact_frames", double(m_contactFrames)});
  if (m_resection) {
    counters.push_back({"removed_tetrahedra", double(m_resection->totals().removedTets)});
    counters.push_back({"remaining_tetrahedra", double(m_resection->remaining().aliveCount())});
    counters.push_back({"boundary_faces_now", double(m_resection->boundaryFaces())});
    counters.push_back({"loose_pieces_removed", double(m_resection->loosePieces())});
    counters.push_back({"loose_tetrahedra_removed", double(m_resection->looseTets())});
    counters.push_back({"fragments_removed", double(m_resection->fragments())});
  }
  counters.push_back({"queries", double(m_queries)});  // contact, sweep, overlap and broad-phase queries of the run
  if (m_positions) {
    counters.push_back({"deformation_frames", double(m_deformationFrames)});
    counters.push_back({"largest_displacement_bound_mm", m_largestBound});
    if (m_rejectedFrames) counters.push_back({"rejected_position_frames", double(m_rejectedFrames)});
    if (m_shapeFailures) counters.push_back({"shape_failures", double(m_shapeFailures)});
  }
  // The most nodes the tool's force was shared among in a frame: what each
  // reader of the node forces copies on the haptic thread.
  if (!m_nodeSlot.empty()) counters.push_back({"largest_node_force_count", double(m_largestNodeForceCount)});
  if (m_bound) m_backend->reportCounters(counters);
}

void TetraBrain::reportFacts(std::vector<Fact>& facts) const { facts.push_back({"backend", d_backend.value()}); }

}  // namespace trephine::tetra
