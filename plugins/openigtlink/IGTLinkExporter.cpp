#include "plugins/openigtlink/IGTLinkExporter.h"

#include <algorithm>
#include <stdexcept>

#include "framework/core/ChannelHub.h"
#include "framework/core/Lifecycle.h"
#include "framework/data/TetTopology.h"
#include "plugins/openigtlink/IgtlExportMessages.h"
#include "plugins/openigtlink/IgtlMessages.h"

namespace trephine::openigtlink {
namespace {

int columnOf(const std::vector<std::string>& columns, const std::string& name) {
  const auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : int(it - columns.begin());
}

constexpr size_t kMaxQueuedBytes = size_t(256) << 20;  // a client this far behind is let go
// Bytes of the skull encoded a tick for new clients (all of them together):
// about a millisecond of the 30 Hz group's 33 ms.
constexpr size_t kWelcomeBytesPerTick = size_t(2) << 20;

std::shared_ptr<const Message> shared(Message m) { return std::make_shared<const Message>(std::move(m)); }

}  // namespace

void IGTLinkExporter::init(InitContext& context) {
  if (const std::string problem = d_server.hostProblem(); !problem.empty()) context.error(d_server.host, problem);
  for (const Field<std::string>* name : {&d_deviceName, &d_proxyName, &d_forceName, &d_skullName, &d_brainName})
    if (name->value().empty() || name->value().size() > kDeviceNameSize)
      context.error(*name, "an OpenIGTLink device name has 1 to 20 characters");
  if (l_force) {
    const std::vector<std::string> columns = l_force->sampleColumns();
    m_device = columnOf(columns, "device_x");
    m_proxy = columnOf(columns, "proxy_x");
    m_forceColumn = columnOf(columns, "force_x");
    m_orientation = columnOf(columns, "tool_qw");
    if (m_device < 0 || m_proxy < 0 || m_forceColumn < 0)
      context.error(l_force, "publishes no device_x, proxy_x and force_x columns (a ForceFeedback does)");
    else
      m_samples = context.channels().subscribe<Sample>(*l_force.boundComponent(), kSampleChannel);
  }
  if (l_skull) {
    const VoxelGrid& grid = l_skull->voxelGrid();
    for (const int32_t n : {grid.nx, grid.ny, grid.nz})
      if (n > 65535) context.error(l_skull, "a volume of more than 65535 voxels along an axis (OpenIGTLink's limit)");
    m_codes.assign(grid.codes, grid.codes + grid.voxelCount());
    m_grid = grid;
    m_grid.codes = m_codes.data();
    if (l_skull->drills()) {
      m_edits = std::make_shared<ChangeQueue<VoxelEdit>>(size_t(1) << 18);
      l_skull->recordEdits(m_edits);
    }
  }
  if (l_brain) {
    const TetMesh& mesh = l_brain->mesh();
    m_topology = TetTopology(mesh);
    m_remaining.emplace(mesh, m_topology);
    // A resected brain's surface is what remains (nothing is pushed otherwise).
    m_removals = &l_brain->subscribeRemovals();
    collectSurface();
    m_nodes = mesh.nodes;
    if (l_brain->deformer())
      m_positions = context.channels().subscribe<NodePositions>(*l_brain->deformer(), kNodePositionsChannel);
  }
}

void IGTLinkExporter::collectSurface() {
  // Only the nodes on the boundary are sent, numbered in the order they are met.
  const TetMesh& mesh = l_brain->mesh();
  m_triangles.clear();
  m_surfaceNodes.clear();
  std::vector<int32_t> surfaceIndex(mesh.nodeCount(), -1);
  const auto surface = [&](int32_t node) {
    if (surfaceIndex[size_t(node)] < 0) {
      surfaceIndex[size_t(node)] = int32_t(m_surfaceNodes.size());
      m_surfaceNodes.push_back(node);
    }
    return surfaceIndex[size_t(node)];
  };
  const auto add = [&](int32_t t, int f) {
    const auto& tet = mesh.tets[size_t(t)];
    m_triangles.push_back({surface(tet[(f + 1) % 4]), surface(tet[(f + 2) % 4]), surface(tet[(f + 3) % 4])});
  };
  // The first boundary's faces that remain, in its order; then the faces a
  // resection exposed (inside the mesh at first).
  for (const BoundaryFace& f : m_topology.boundaryFaces())
    if (m_remaining->onBoundary(f.tet, f.face)) add(f.tet, f.face);
  if (m_remaining->aliveCount() == mesh.tetCount()) return;
  for (int32_t t = 0; t < int32_t(mesh.tetCount()); ++t)
    for (int f = 0; f < 4; ++f)
      if (!m_topology.isBoundary(t, f) && m_remaining->onBoundary(t, f)) add(t, f);
}

bool IGTLinkExporter::applyRemovals() {
  if (!m_removals) return false;
  m_removedBatch.clear();
  m_removals->drain([&](int32_t tet) { m_removedBatch.push_back(tet); });
  if (m_removedBatch.empty() || m_remaining->remove(m_removedBatch).removedTets.empty()) return false;
  collectSurface();
  return true;
}

void IGTLinkExporter::prepare(const RunPlan& plan) {
  if (l_brain && l_brain->deformer() && !m_positions)
    throw std::runtime_error("the deformation of " + l_brain.boundComponent()->path() +
                             " starts after this component: place the IGTLinkExporter after it in the scene");
  m_server.reset();
  // In virtual time there is no one to stream to.
  if (plan.realtime)
    m_server = std::make_unique<IgtlBroadcaster>(d_server.host.value(), d_server.portNumber(),
                                                 static_cast<size_t>(d_server.maxClients.value()), kMaxQueuedBytes,
                                                 d_server.clientTimeout.value());
  m_welcomes.clear();
}

bool IGTLinkExporter::applySkullEdits() {
  if (!m_edits) return false;
  const int64_t nx = m_grid.nx, ny = m_grid.ny;
  const size_t n = m_edits->drain([&](const VoxelEdit& e) {
    m_codes[size_t(e.voxel)] = e.code;
    const std::array<int64_t, 3> ijk{e.voxel % nx, (e.voxel / nx) % ny, e.voxel / (nx * ny)};
    if (!m_skullChanged) {
      m_changedFirst = m_changedLast = ijk;
      m_skullChanged = true;
    }
    for (int a = 0; a < 3; ++a) {
      m_changedFirst[a] = std::min(m_changedFirst[a], ijk[a]);
      m_changedLast[a] = std::max(m_changedLast[a], ijk[a]);
    }
  });
  return n > 0;
}

void IGTLinkExporter::sendChangedBlock(double t) {
  std::array<int32_t, 3> offset{}, size{};
  for (int a = 0; a < 3; ++a) {
    offset[a] = int32_t(m_changedFirst[a]);
    size[a] = int32_t(m_changedLast[a] - m_changedFirst[a] + 1);
  }
  m_server->broadcast(shared(imageMessage(d_skullName.value(), toTimestamp(t), m_grid, offset, size)));
  ++m_subvolumes;
  m_skullChanged = false;
  m_lastImage = t;
}

void IGTLinkExporter::continueWelcomes(double t) {
  if (m_welcomes.empty()) return;
  const size_t sliceBytes = size_t(m_grid.nx) * size_t(m_grid.ny) * sizeof(int16_t);
  size_t budget = kWelcomeBytesPerTick;
  // The furthest along first (those that came first: clients that keep
  // coming never starve one that came before them); clients at the same
  // slice (those that came together) share each slab's encoding.
  std::sort(m_welcomes.begin(), m_welcomes.end(),
            [](const Welcome& a, const Welcome& b) { return a.nextSlice > b.nextSlice; });
  for (size_t i = 0; i < m_welcomes.size() && budget > 0;) {
    const int32_t first = m_welcomes[i].nextSlice;
    const int32_t slices = int32_t(std::clamp<size_t>(budget / std::max<size_t>(sliceBytes, 1), 1,
                                                      size_t(m_grid.nz - first)));
    auto slab = shared(imageMessage(d_skullName.value(), toTimestamp(t), m_grid, {0, 0, first},
                                    {int32_t(m_grid.nx), int32_t(m_grid.ny), slices}));
    budget -= std::min(budget, size_t(slices) * sliceBytes);
    ++m_welcomeSlabs;
    for (; i < m_welcomes.size() && m_welcomes[i].nextSlice == first; ++i) {
      // A client gone meanwhile is owed nothing more; one that has not taken
      // its last slab yet gets this one later (a slow link is never buried).
      const std::optional<size_t> queued = m_server->queued(m_welcomes[i].client);
      if (!queued) {
        m_welcomes[i].nextSlice = m_grid.nz;
      } else if (*queued <= kWelcomeBytesPerTick) {
        m_server->sendTo(m_welcomes[i].client, slab);
        m_welcomes[i].nextSlice = first + slices;
      }
    }
  }
  std::erase_if(m_welcomes, [&](const Welcome& w) { return w.nextSlice >= m_grid.nz; });
}

void IGTLinkExporter::sendSurface(bool toNewOnly, double t) {
  m_surfacePoints.resize(m_surfaceNodes.size());
  for (size_t i = 0; i < m_surfaceNodes.size(); ++i) m_surfacePoints[i] = m_nodes[size_t(m_surfaceNodes[i])];
  auto message = shared(polyDataMessage(d_brainName.value(), toTimestamp(t), m_surfacePoints, m_triangles));
  if (toNewOnly) {
    m_server->sendToNew(message);
  } else {
    m_server->broadcast(message);
    m_brainMoved = false;
    m_lastSurface = t;
  }
  ++m_surfaces;
}

void IGTLinkExporter::tick(const TickContext& context) {
  applySkullEdits();
  if (applyRemovals()) m_brainMoved = true;  // sent as the moved surface is
  if (m_positions && m_positions->fetch()) {
    const NodePositions& p = m_positions->read();
    if (p.step != m_nodesStep && p.positions.size() == m_nodes.size()) {
      m_nodes = p.positions;
      m_nodesStep = p.step;
      m_brainMoved = true;
    }
  }
  if (!m_server) return;
  const double t = context.t;
  // New clients get the brain as it is now, and the skull in slabs over the
  // next ticks (each slab as the skull is when it goes: with the changed
  // blocks broadcast meanwhile, the client holds the skull as it is).
  if (m_server->poll() > 0) {
    if (l_skull)
      for (const uint64_t client : m_server->newClients()) m_welcomes.push_back({client, 0});
    if (l_brain) sendSurface(true, t);
    if (l_skull) ++m_images;
  }
  if (l_skull) continueWelcomes(t);
  if (m_samples) {
    m_samples->fetch();
    const Sample& s = m_samples->read();
    const auto vec = [&](int c) { return Vec3(s.values[c], s.values[c + 1], s.values[c + 2]); };
    Quat q = Quat::Identity();
    if (m_orientation >= 0) {
      const Quat read(s.values[m_orientation], s.values[m_orientation + 1], s.values[m_orientation + 2],
                      s.values[m_orientation + 3]);
      if (read.norm() > 0.5) q = read.normalized();
    }
    const uint64_t stamp = toTimestamp(s.t);
    m_server->broadcast(shared(transformMessage(d_deviceName.value(), stamp, vec(m_device), q)));
    m_server->broadcast(shared(transformMessage(d_proxyName.value(), stamp, vec(m_proxy), q)));
    auto sensor = std::make_shared<Message>(kForceSensorMessageSize);
    const Vec3 force = vec(m_forceColumn);
    encodeForceSensor(d_forceName.value(), stamp, force.allFinite() ? lpsToRas(force) : Vec3::Zero(),
                      std::span<unsigned char, kForceSensorMessageSize>(sensor->data(), kForceSensorMessageSize));
    m_server->broadcast(sensor);
    ++m_poses;
  }
  if (m_skullChanged && t - m_lastImage >= d_imageInterval.value()) sendChangedBlock(t);
  if (m_brainMoved && t - m_lastSurface >= d_surfaceInterval.value()) sendSurface(false, t);
}

void IGTLinkExporter::finish(FinishContext& context) {
  (void)context;
  if (m_edits && m_edits->dropped())
    context.error(*this, "fell behind the drill: " + std::to_string(m_edits->dropped()) +
                             " voxel changes were not streamed; the skull a client holds is stale");
  if (m_server) {
    m_accepted = m_server->accepted();
    m_refused = m_server->refused();
    m_slow = m_server->dropped();
    m_sent = m_server->messagesSent();
  }
  m_server.reset();  // clients are disconnected; the counters were kept
}

void IGTLinkExporter::reportCounters(std::vector<Counter>& counters) const {
  const auto add = [&](const char* name, uint64_t v) { counters.push_back({name, static_cast<double>(v)}); };
  add("pose_frames", m_poses);
  add("images_whole", m_images);
  add("images_partial", m_subvolumes);
  add("welcome_slabs", m_welcomeSlabs);
  add("surfaces", m_surfaces);
  add("clients_accepted", m_server ? m_server->accepted() : m_accepted);
  add("clients_refused", m_server ? m_server->refused() : m_refused);
  add("clients_slow", m_server ? m_server->dropped() : m_slow);
  add("messages_sent", m_server ? m_server->messagesSent() : m_sent);
}

void IGTLinkExporter::reportFacts(std::vector<Fact>& facts) const {
  if (m_server) facts.push_back({"listening", d_server.host.value() + ":" + std::to_string(m_server->port())});
}

}  // namespace trephine::openigtlink
