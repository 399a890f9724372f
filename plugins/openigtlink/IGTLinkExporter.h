#pragma once
// Streams a running scene to 3D Slicer's OpenIGTLinkIF (or any OpenIGTLink
// client), at its own rate in a group of its own: an OpenIGTLink server on
// 127.0.0.1:port (`host` binds elsewhere, on request only) that sends every
// client that connects
//   TRANSFORM  `deviceName`, `proxyName`  the device and the proxy (mm), the tool's orientation;
//   SENSOR     `forceName`                the force on the hand (N), three float64;
//   IMAGE      `skullName`                the skull's codes (int16), whole to a client that connects,
//                                         in slabs of slices over its first ticks (2 MB of them a
//                                         tick for all new clients together: clients that come and
//                                         go cost the group no deadline), then only the block the
//                                         drill changed (the protocol's sub-volume), at most every
//                                         `imageInterval`;
//   POLYDATA   `brainName`                the brain's boundary surface at its current node positions,
//                                         when a client connects and then when it moved, at most
//                                         every `surfaceInterval`.
// Everything goes in RAS (3D Slicer's frame), turned from the scene's LPS.
// Only what the links name is sent. It runs in real time only (trephine run
// --realtime): in virtual time there is no one to stream to. The haptic and
// FEM threads only copy into channels; the messages are packed and sent here.
#include <memory>
#include <optional>

#include "framework/channels/Channel.h"
#include "framework/channels/ChangeQueue.h"
#include "framework/core/Component.h"
#include "framework/core/SampleSource.h"
#include "framework/data/MeshDeformation.h"
#include "framework/data/RemainingMesh.h"
#include "framework/data/TetTopology.h"
#include "framework/geometry/DeformableMesh.h"
#include "framework/geometry/DrillableVolume.h"
#include "plugins/openigtlink/IgtlBroadcaster.h"
#include "plugins/openigtlink/IgtlServerFields.h"

namespace trephine::openigtlink {

class IGTLinkExporter final : public Component {
 public:
  static constexpr std::string_view kTypeName = "IGTLinkExporter";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void tick(const TickContext& context) override;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void reportFacts(std::vector<Fact>& facts) const override;

  uint16_t listeningPort() const { return m_server ? m_server->port() : 0; }

 private:
  // The block of the skull the drill changed since the last one, to every client.
  void sendChangedBlock(double t);
  void sendSurface(bool toNewOnly, double t);
  bool applySkullEdits();

  Link<SampleSource> l_force{
      this, "force", {.help = "ForceFeedback whose device, proxy and force are streamed", .initOnly = true}};
  Link<DrillableVolume> l_skull{
      this, "skull", {.help = "Skull whose codes are streamed as an IMAGE (again where drilled)", .initOnly = true}};
  Link<DeformableMesh> l_brain{
      this, "brain", {.help = "Brain whose boundary surface is streamed as POLYDATA", .initOnly = true}};
  RateField d_rate{this, 30.0, "Messages per second of the poses and the force"};
  IgtlServerFields d_server{this, 18945, "TCP port 3D Slicer's OpenIGTLinkIF connects to (0: any free one)"};
  Field<std::string> d_deviceName{this, "deviceName", "TrephineDevice", {.help = "TRANSFORM of the device"}};
  Field<std::string> d_proxyName{this, "proxyName", "TrephineProxy", {.help = "TRANSFORM of the proxy"}};
  Field<std::string> d_forceName{this, "forceName", "TrephineForce", {.help = "SENSOR of the force (N)"}};
  Field<std::string> d_skullName{this, "skullName", "TrephineSkull", {.help = "IMAGE of the skull"}};
  Field<std::string> d_brainName{this, "brainName", "TrephineBrain", {.help = "POLYDATA of the brain's surface"}};
  Field<double> d_imageInterval{this,
                                "imageInterval",
                                0.5,
                                {.help = "While the skull is drilled, its changed block is sent at most this often",
                                 .unit = "s",
                                 .min = 0.0}};
  Field<double> d_surfaceInterval{this,
                                  "surfaceInterval",
                                  0.1,
                                  {.help = "While the brain moves, its surface is sent at most this often",
                                   .unit = "s",
                                   .min = 0.0}};

  std::unique_ptr<IgtlBroadcaster> m_server;
  // The force's samples.
  std::optional<ChannelReader<Sample>> m_samples;
  int m_device = -1, m_proxy = -1, m_forceColumn = -1, m_orientation = -1;
  // The skull: a copy of its codes kept current from the drill's edits.
  std::shared_ptr<ChangeQueue<VoxelEdit>> m_edits;
  std::vector<VoxelCode> m_codes;
  VoxelGrid m_grid;
  std::array<int64_t, 3> m_changedFirst{}, m_changedLast{};
  bool m_skullChanged = false;
  double m_lastImage = -INFINITY;
  // The brain: its boundary triangles, and its nodes as last read.
  std::optional<ChannelReader<NodePositions>> m_positions;
  std::vector<std::array<int32_t, 3>> m_triangles;  // into m_surfaceNodes
  std::vector<int32_t> m_surfaceNodes;              // the mesh nodes on its boundary
  std::vector<Vec3> m_nodes;                        // all of them, as last read
  std::vector<Vec3> m_surfacePoints;                // those on the boundary
  uint64_t m_nodesStep = 0;
  bool m_brainMoved = false;
  // A resected brain: what remains, followed from its removals (this
  // component's thread); the surface sent is its boundary now.
  ChangeQueue<int32_t>* m_removals = nullptr;
  TetTopology m_topology;
  std::optional<RemainingMesh> m_remaining;
  std::vector<int32_t> m_removedBatch;
  // The boundary triangles and their nodes, of what remains.
  void collectSurface();
  bool applyRemovals();
  double m_lastSurface = -INFINITY;
  // A new client gets the skull in slabs of slices, a budget of bytes a tick
  // across all of them (continueWelcomes), so that clients that come and go
  // cost the group no deadline: the next slice each is owed.
  struct Welcome {
    uint64_t client = 0;
    int32_t nextSlice = 0;
  };
  void continueWelcomes(double t);
  std::vector<Welcome> m_welcomes;
  uint64_t m_images = 0, m_subvolumes = 0, m_surfaces = 0, m_poses = 0, m_welcomeSlabs = 0;
  uint64_t m_accepted = 0, m_refused = 0, m_slow = 0, m_sent = 0;  // the server's, kept when it closes
};

}  // namespace trephine::openigtlink
