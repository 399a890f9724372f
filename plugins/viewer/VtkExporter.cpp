#include "plugins/viewer/VtkExporter.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "framework/core/AtomicFile.h"
#include "framework/core/Lifecycle.h"
#include "framework/formats/volume/VolumeWriter.h"
#include "framework/geometry/HeldTools.h"
#include "plugins/viewer/LiveServer.h"

namespace trephine::viewer {

namespace {

// The index of `name` among the source's columns, or -1.
int columnOf(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : int(it - columns.begin());
}

std::string numbered(const std::string& stem, uint64_t frame, const char* extension) {
  char digits[24];
  std::snprintf(digits, sizeof digits, "_%05llu", static_cast<unsigned long long>(frame));
  return stem + digits + extension;
}

}  // namespace

void VtkExporter::init(InitContext& context) {
  if (!l_brain && !l_force && !l_skull)
    context.error(*this, "names nothing to write: link a brain, a skull, a force, or several");
  if (l_skull) {
    DrillableVolume& skull = *l_skull;
    const VoxelGrid& grid = skull.voxelGrid();
    m_skullCodes.assign(grid.codes, grid.codes + grid.voxelCount());
    m_skullGrid = grid;
    m_skullGrid.codes = m_skullCodes.data();
    m_skullSurface.build(m_skullGrid);
    m_blockChanged.assign(m_skullSurface.blockCount(), 1);
    m_blockFiles.assign(m_skullSurface.blockCount(), "");
    if (skull.drills()) {
      // A drill frame lowers at most a few thousand codes (a 466-point shell,
      // 8 corners each); at 30 Hz the ring holds some 70 frames of that.
      m_edits = std::make_shared<ChangeQueue<VoxelEdit>>(size_t(1) << 18);
      skull.recordEdits(m_edits);
    }
  }
  if (l_brain) {
    DeformableMesh& brain = *l_brain;
    const TetMesh& mesh = brain.mesh();
    m_cells.emplace(std::span<const std::array<int32_t, 4>>(mesh.tets), std::span<const int32_t>(mesh.labels),
                    mesh.nodeCount());
    // A resected brain's files hold what remains (nothing is pushed otherwise).
    m_removals = &brain.subscribeRemovals();
    m_removedTets.assign(mesh.tetCount(), 0);
    m_displacement.values.assign(3 * brain.mesh().nodeCount(), 0.0f);
    m_force.values.assign(3 * brain.mesh().nodeCount(), 0.0f);
    if (brain.deformer())
      m_positions = context.channels().subscribe<NodePositions>(*brain.deformer(), kNodePositionsChannel);
    // Stresses from a deformer that computes them (it does so only when read).
    if (brain.deformer() && context.channels().published(*brain.deformer(), kElementStressChannel)) {
      m_elementStress = context.channels().subscribe<ElementStress>(*brain.deformer(), kElementStressChannel);
      m_vonMises.values.assign(mesh.tets.size(), 0.0f);
    }
    m_nodeForces = context.channels().subscribe<NodeForces>(*l_brain.boundComponent(), kNodeForcesChannel);
  }
  if (l_force) {
    const std::vector<std::string> columns = l_force->sampleColumns();
    m_device = columnOf(columns, "device_x");
    m_proxy = columnOf(columns, "proxy_x");
    m_forceColumn = columnOf(columns, "force_x");
    m_normal = columnOf(columns, "normal_x");
    m_penetration = columnOf(columns, "penetration");
    m_toolRadius = columnOf(columns, "tool_radius");
    m_toolInHand = columnOf(columns, "tool_in_hand");
    m_toolOrientation = columnOf(columns, "tool_qw");
    if (const auto* held = dynamic_cast<const HeldTools*>(l_force.boundComponent()))
      for (const ShellTool* tool : held->heldTools()) m_toolSurfaces.push_back(tool->displaySurface());
    if (m_device < 0 || m_proxy < 0 || m_forceColumn < 0)
      context.error(l_force, "publishes no device_x, proxy_x and force_x columns (a ForceFeedback does)");
    m_samples = context.channels().subscribe<Sample>(*l_force.boundComponent(), kSampleChannel);
  }
}

void VtkExporter::prepare(const RunPlan& plan) {
  if (l_brain && l_brain->deformer() && !m_positions)
    throw std::runtime_error("the deformation of " + l_brain.boundComponent()->path() + " starts after this component: place the " +
                             "VtkExporter after it in the scene, or its files show the brain at rest");
  m_root = plan.outputDirectory;
  m_live.reset();
  if (plan.liveViewPort >= 0) startLiveView(plan);
  m_collection = {};
  m_frames = m_files = m_failed = 0;
  m_firstFailure.clear();
  m_brainWritten = false;
  m_skullChanged = true;  // the first frame writes every block
  std::fill(m_blockChanged.begin(), m_blockChanged.end(), 1);
  m_lastSkullWrite = -INFINITY;
  m_skullEdits = m_skullFiles = 0;
  m_removed.clear();
  m_folder.reset();
  if (m_root.empty()) return;
  // Reached from the run's folder without following a link: a `vtk` planted
  // there as a link to elsewhere is refused, not written into.
  try {
    m_folder = OutputFolder::open(m_root).subfolder(d_directory.value());
  } catch (const FileWriteError& e) {
    throw std::runtime_error(e.what());
  }
  if (l_skull) writeSkullVolume();
}

void VtkExporter::writeSkullVolume() {
  const VoxelGrid& g = m_skullGrid;
  DensityVolume volume({g.nx, g.ny, g.nz}, g.spacing, g.corner + 0.5 * g.spacing, g.encoding);
  std::copy(m_skullCodes.begin(), m_skullCodes.end(), volume.codes());
  // Not listed in the index (it does not change in time): beside it.
  try {
    formats::writeMetaImage(volume, OutputPath(*m_folder, "skull_density.mhd"), /*compress=*/true);
    // What the volume alone does not say: the skull's isovalue.
    writeFileAtomically(*m_folder, "skull_volume.json", [&](std::ostream& out) {
      out.precision(9);
      out << "{\"density\": \"skull_density.mhd\", \"removed\": \"skull_removed.csv\", \"isovalue\": "
          << g.encoding.density(0) + g.encoding.scale * g.isoCode << "}\n";
    });
    m_files += 3;
  } catch (const std::exception& e) {
    if (m_failed++ == 0) m_firstFailure = e.what();
  }
}

void VtkExporter::writeRemovedVoxels() {
  const int64_t nx = m_skullGrid.nx, ny = m_skullGrid.ny;
  try {
    writeFileAtomically(*m_folder, "skull_removed.csv", [&](std::ostream& out) {
      out << "i,j,k,t\n";
      char line[96];
      for (const RemovedVoxel& r : m_removed) {
        std::snprintf(line, sizeof line, "%lld,%lld,%lld,%.9g\n", static_cast<long long>(r.voxel % nx),
                      static_cast<long long>((r.voxel / nx) % ny), static_cast<long long>(r.voxel / (nx * ny)), r.t);
        out << line;
      }
    });
    ++m_files;
  } catch (const std::exception& e) {
    if (m_failed++ == 0) m_firstFailure = e.what();
  }
}

template <class Write>
void VtkExporter::attempt(const std::string& file, double t, int part, Write&& write) {
  try {
    write(OutputPath(*m_folder, file));
    m_collection.add(t, d_directory.value() + "/" + file, part);
    ++m_files;
  } catch (const std::exception& e) {
    if (m_failed++ == 0) m_firstFailure = e.what();
  }
}

bool VtkExporter::updateBrain() {
  const DeformableMesh& brain = *l_brain;
  const std::vector<Vec3>& rest = brain.mesh().nodes;
  const bool moved = m_positions && (m_positions->fetch(), m_positions->read().positions.size() == rest.size());
  const bool newForces = m_nodeForces->fetch();  // every frame: a deforming brain's files carry them too
  bool removed = false;
  if (m_removals)
    m_removals->drain([&](int32_t tet) {
      if (tet >= 0 && size_t(tet) < m_removedTets.size() && !m_removedTets[size_t(tet)]) {
        m_removedTets[size_t(tet)] = 1;
        removed = true;
      }
    });
  if (removed) compressRemainingCells();
  bool newStress = false;
  if (m_elementStress && m_elementStress->fetch() &&
      m_elementStress->read().vonMises.size() == m_removedTets.size()) {
    newStress = m_elementStress->read().vonMises != m_vonMisesAll || m_cellsChanged;
    m_vonMisesAll = m_elementStress->read().vonMises;
    // Per cell written: the remaining tetrahedra's.
    m_vonMises.values.clear();
    for (size_t t = 0; t < m_vonMisesAll.size(); ++t)
      if (!m_removedTets[t]) m_vonMises.values.push_back(m_vonMisesAll[t]);
  }
  const std::vector<Vec3>& nodes = moved ? m_positions->read().positions : rest;
  // A brain at rest between touches (the FEM still publishes) is not written
  // again: its last file stands.
  if (m_brainWritten && !newForces && !newStress && !m_cellsChanged && nodes == m_writtenNodes) return false;
  m_cellsChanged = false;
  m_writtenNodes = nodes;
  for (size_t i = 0; i < nodes.size(); ++i)
    for (int a = 0; a < 3; ++a) m_displacement.values[3 * i + a] = float(nodes[i][a] - rest[i][a]);
  std::fill(m_force.values.begin(), m_force.values.end(), 0.0f);
  for (const NodeForce& f : m_nodeForces->read().forces)
    if (f.node >= 0 && size_t(f.node) < nodes.size())
      for (int a = 0; a < 3; ++a) m_force.values[3 * size_t(f.node) + a] += float(f.force[a]);
  m_brainWritten = true;
  return true;
}

void VtkExporter::compressRemainingCells() {
  const TetMesh& mesh = l_brain->mesh();
  std::vector<std::array<int32_t, 4>> tets;
  std::vector<int32_t> labels;
  for (size_t t = 0; t < mesh.tetCount(); ++t) {
    if (m_removedTets[t]) continue;
    tets.push_back(mesh.tets[t]);
    if (!mesh.labels.empty()) labels.push_back(mesh.labels[t]);
  }
  m_cells.emplace(std::span<const std::array<int32_t, 4>>(tets), std::span<const int32_t>(labels), mesh.nodeCount());
  if (!m_vonMisesAll.empty()) {
    m_vonMises.values.clear();
    for (size_t t = 0; t < m_vonMisesAll.size(); ++t)
      if (!m_removedTets[t]) m_vonMises.values.push_back(m_vonMisesAll[t]);
  }
  m_cellsChanged = true;
}

void VtkExporter::writeBrain(double t) {
  attempt(numbered("brain", m_frames, ".vtu"), t, 0, [&](const OutputPath& f) {
    formats::writeTetGrid(m_writtenNodes, *m_cells, {m_displacement, m_force},
                          m_elementStress ? std::vector<formats::VtkDataArray>{m_vonMises} : std::vector<formats::VtkDataArray>{},
                          f);
  });
}

std::optional<Vec3> VtkExporter::contactPoint(const Sample& s) const {
  if (m_normal < 0 || m_toolRadius < 0) return std::nullopt;
  const Vec3 normal(s.values[m_normal], s.values[m_normal + 1], s.values[m_normal + 2]);
  if (normal.squaredNorm() < 0.5) return std::nullopt;  // no contact: no normal
  const Vec3 proxy(s.values[m_proxy], s.values[m_proxy + 1], s.values[m_proxy + 2]);
  return proxy - s.values[m_toolRadius] * normal;
}

void VtkExporter::writeTool(double t) {
  const Sample& s = m_samples->read();
  auto vec = [&](int column) { return column < 0 ? Vec3::Zero() : Vec3(s.values[column], s.values[column + 1], s.values[column + 2]); };
  formats::VtkPolyData tool;
  tool.points = {vec(m_device), vec(m_proxy)};
  const std::optional<Vec3> contact = contactPoint(s);
  if (contact) tool.points.push_back(*contact);
  const size_t n = tool.points.size();
  for (size_t i = 0; i < n; ++i) tool.vertices.push_back(int32_t(i));
  tool.lines = {{0, 1}};
  // Each array holds one value for every point: the frame's value.
  auto perPoint = [n](std::string name, std::initializer_list<float> value) {
    formats::VtkDataArray array{std::move(name), int(value.size()), {}};
    for (size_t i = 0; i < n; ++i) array.values.insert(array.values.end(), value);
    return array;
  };
  const Vec3 force = vec(m_forceColumn), normal = vec(m_normal);
  const float penetration = m_penetration < 0 ? 0.0f : float(s.values[m_penetration]);
  tool.pointData = {perPoint("force", {float(force.x()), float(force.y()), float(force.z())}),
                    perPoint("normal", {float(normal.x()), float(normal.y()), float(normal.z())}),
                    perPoint("penetration", {penetration})};
  if (m_toolRadius >= 0) tool.pointData.push_back(perPoint("radius", {float(s.values[m_toolRadius])}));  // mm
  attempt(numbered("tool", m_frames, ".vtp"), t, 1, [&](const OutputPath& f) { formats::writePolyData(tool, f); });
}

bool VtkExporter::placeToolSurface(const Sample& s) {
  if (m_toolSurfaces.empty() || m_toolInHand < 0 || m_toolOrientation < 0) return false;
  const double index = s.values[m_toolInHand];
  if (!(index >= 0 && index < double(m_toolSurfaces.size()))) return false;
  const TriangleMesh& surface = m_toolSurfaces[size_t(index)];
  const Quat q(s.values[m_toolOrientation], s.values[m_toolOrientation + 1], s.values[m_toolOrientation + 2],
               s.values[m_toolOrientation + 3]);
  if (!(q.norm() > 0.5)) return false;
  const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
  const Vec3 proxy(s.values[m_proxy], s.values[m_proxy + 1], s.values[m_proxy + 2]);
  m_toolShape.points.resize(surface.vertices.size());
  for (size_t i = 0; i < surface.vertices.size(); ++i) m_toolShape.points[i] = proxy + R * surface.vertices[i];
  m_toolShape.triangles = surface.triangles;
  return true;
}

void VtkExporter::writeToolShape(double t) {
  attempt(numbered("toolshape", m_frames, ".vtp"), t, 3,
          [&](const OutputPath& f) { formats::writePolyData(m_toolShape, f); });
}

bool VtkExporter::applySkullEdits(double t) {
  if (!m_edits) return false;
  std::array<int64_t, 3> first{INT64_MAX, INT64_MAX, INT64_MAX}, last{INT64_MIN, INT64_MIN, INT64_MIN};
  const int64_t nx = m_skullGrid.nx, ny = m_skullGrid.ny;
  const double iso = m_skullGrid.isoCode;
  const size_t n = m_edits->drain([&](const VoxelEdit& e) {
    VoxelCode& code = m_skullCodes[size_t(e.voxel)];
    if (code >= iso && e.code < iso) m_removed.push_back({int64_t(e.voxel), float(t)});
    code = e.code;
    const std::array<int64_t, 3> ijk{e.voxel % nx, (e.voxel / nx) % ny, e.voxel / (nx * ny)};
    for (int a = 0; a < 3; ++a) {
      first[a] = std::min(first[a], ijk[a]);
      last[a] = std::max(last[a], ijk[a]);
    }
  });
  if (n == 0) return false;
  m_skullEdits += n;
  for (size_t block : m_skullSurface.update(m_skullGrid, first, last)) {
    m_blockChanged[block] = 1;
    if (m_live) m_liveBlockChanged[block] = 1;
  }
  return true;
}

void VtkExporter::writeSkull(double t) {
  for (size_t b = 0; b < m_blockChanged.size(); ++b) {
    if (!m_blockChanged[b]) continue;
    m_blockChanged[b] = 0;
    const TriangleMesh& mesh = m_skullSurface.block(b);
    if (mesh.triangles.empty()) {
      m_blockFiles[b].clear();
      continue;
    }
    formats::VtkPolyData surface;
    surface.points = mesh.vertices;
    surface.triangles = mesh.triangles;
    const std::string name = numbered("b" + std::to_string(b), m_frames, ".vtp");
    try {
      formats::writePolyData(surface, OutputPath(*m_folder, "skull/" + name));
      m_blockFiles[b] = "skull/" + name;
      ++m_files;
    } catch (const std::exception& e) {
      if (m_failed++ == 0) m_firstFailure = e.what();
    }
  }
  // Each block at its own index: a block that empties or fills moves no other.
  std::vector<std::pair<size_t, std::string>> files;
  for (size_t b = 0; b < m_blockFiles.size(); ++b)
    if (!m_blockFiles[b].empty()) files.push_back({b, m_blockFiles[b]});
  attempt(numbered("skull", m_frames, ".vtm"), t, 2, [&](const OutputPath& f) {
    formats::writeMultiBlock(files, f);
  });
  ++m_skullFiles;
  m_skullChanged = false;
  m_lastSkullWrite = t;
}

void VtkExporter::tick(const TickContext& context) {
  if (l_skull) m_skullChanged = applySkullEdits(context.t) || m_skullChanged;  // the copy follows even with no files
  const bool files = !m_root.empty();
  if (!files && !m_live) return;  // the run writes no files and streams nothing
  if (l_brain && updateBrain()) {
    if (files) writeBrain(context.t);
    if (m_live) m_live->sendNodes(context.t, m_writtenNodes);
  }
  if (l_force) {
    m_samples->fetch();
    const bool shaped = placeToolSurface(m_samples->read());
    if (files) writeTool(context.t);
    if (files && shaped) writeToolShape(context.t);
    if (m_live) sendTool(context.t);
    if (m_live && shaped) m_live->sendToolSurface(m_toolShape.points, m_toolShape.triangles);
  }
  if (l_skull && files && m_skullChanged && context.t - m_lastSkullWrite >= d_skullInterval.value())
    writeSkull(context.t);
  if (l_skull && m_live) {
    // The drill's blocks, whole, each frame they change (and the coarse
    // surface around them replaced by the full one).
    for (size_t b = 0; b < m_liveBlockChanged.size(); ++b) {
      if (!m_liveBlockChanged[b]) continue;
      m_liveBlockChanged[b] = 0;
      m_liveSkull->fineBlockChanged(b);
    }
  }
  ++m_frames;
}

void VtkExporter::sendTool(double t) {
  const Sample& s = m_samples->read();
  auto vec = [&](int column) {
    return column < 0 ? Vec3::Zero() : Vec3(s.values[column], s.values[column + 1], s.values[column + 2]);
  };
  m_live->sendTool(t, vec(m_device), vec(m_proxy), vec(m_forceColumn), m_toolRadius < 0 ? 0.0 : s.values[m_toolRadius],
                   m_penetration < 0 ? 0.0 : s.values[m_penetration], contactPoint(s));
}

void VtkExporter::startLiveView(const RunPlan& plan) {
  std::vector<std::string> names, kinds;
  if (l_brain) names.push_back("brain"), kinds.push_back("mesh");
  if (l_force) names.push_back("tool"), kinds.push_back("tool");
  if (l_skull) names.push_back("skull"), kinds.push_back("blocks");
  if (!m_toolSurfaces.empty()) names.push_back("toolshape"), kinds.push_back("polydata");
  // The page's title: the run's folder, as a recorded run's viewer has it.
  const std::string runName = plan.outputDirectory.empty()
                                  ? "live"
                                  : "live: " + plan.outputDirectory.lexically_normal().filename().string();
  m_live = std::make_unique<LiveStream>(plan.liveViewPort, runName, plan.duration, names, kinds);
  if (l_brain) {
    m_live->sendCells(l_brain->mesh().tets);
    m_live->sendNodes(0, l_brain->mesh().nodes);
  }
  if (l_skull) {
    m_liveSkull = std::make_unique<LiveSkull>(m_skullGrid, m_skullSurface, size_t(d_viewTriangles.value()),
                                              [this](size_t block, const TriangleMesh& mesh) {
                                                m_live->sendSkullBlock(block, mesh);
                                              });
    m_liveSkull->sendStart();
    m_liveBlockChanged.assign(m_skullSurface.blockCount(), 0);
  }
  std::cout << "view      http://127.0.0.1:" << m_live->port() << "/ (live, while the run goes)" << std::endl;
  if (m_liveSkull)
    std::cout << "          skull: " << m_liveSkull->coarseTriangles() << " triangles (its volume pooled over "
              << m_liveSkull->factor() << "^3 voxels, on its surface), drilled blocks whole" << std::endl;
}

std::string VtkExporter::pvdName() const { return d_directory.value() + ".pvd"; }

void VtkExporter::declareOutputs(std::vector<OutputFile>& outputs) const {
  const BaseField* named = d_directory.isSet() ? &d_directory : nullptr;
  outputs.push_back({pvdName(), named});
  outputs.push_back({d_directory.value(), named, /*folder=*/true});
}

void VtkExporter::finish(FinishContext& context) {
  if (l_skull && !m_root.empty()) {
    // The drill's last changes: the skull as the run left it.
    if (applySkullEdits(context.simulatedTime()) || m_skullChanged) writeSkull(context.simulatedTime());
    writeRemovedVoxels();
  }
  if (m_edits && m_edits->dropped())
    context.error(*this, "fell behind the drill: " + std::to_string(m_edits->dropped()) +
                             " changes of the skull's codes were lost, and its files after the first loss miss them");
  if (m_failed) context.error(*this, std::to_string(m_failed) + " files could not be written; the first: " + m_firstFailure);
  if (context.outputDirectory().empty() || m_root.empty()) return;
  if (!context.claimOutput(*this, pvdName())) return;
  try {
    m_collection.write(OutputPath(OutputFolder::open(context.outputDirectory()), pvdName()));
  } catch (const std::exception& e) {
    context.error(*this, e.what());
  }
}

VtkExporter::VtkExporter() = default;
VtkExporter::~VtkExporter() = default;

void VtkExporter::reportCounters(std::vector<Counter>& counters) const {
  if (m_live) {
    const LiveServer& server = m_live->server();
    counters.push_back({"view_clients", double(server.clients())});
    counters.push_back({"view_skipped_messages", double(server.coalesced())});  // a slow browser got newer ones
    // Misbehaving clients the server refused or closed.
    counters.push_back({"view_refused_requests", double(server.refused())});
    counters.push_back({"view_connections_over_limit", double(server.overLimit())});
    counters.push_back({"view_timeouts", double(server.timedOut())});
    counters.push_back({"view_accept_errors", double(server.acceptErrors())});
  }
  counters.push_back({"frames", double(m_frames)});
  counters.push_back({"files", double(m_files)});
  counters.push_back({"failed_files", double(m_failed)});
  if (l_skull) {
    counters.push_back({"skull_files", double(m_skullFiles)});
    counters.push_back({"skull_edits", double(m_skullEdits)});  // code changes applied to the copy
  }
}

}  // namespace trephine::viewer
