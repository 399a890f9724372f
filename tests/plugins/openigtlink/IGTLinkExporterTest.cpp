// IGTLinkExporter streaming a drilling scene to a client on Debian's
// libopenigtlink (as 3D Slicer's OpenIGTLinkIF receives it): the whole skull
// as an IMAGE when the client connects, then the drilled blocks as
// sub-volumes which, laid over the first image, give the drilled skull voxel
// for voxel; the brain's boundary as POLYDATA; the device's and proxy's
// TRANSFORMs and the force's SENSOR at the exporter's rate, every message's
// CRC checked by the library.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <igtlClientSocket.h>
#include <igtlImageMessage.h>
#include <igtlPolyDataMessage.h>
#include <igtlSensorMessage.h>
#include <igtlTransformMessage.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <set>
#include <thread>
#include <vector>

#include "framework/data/TetTopology.h"
#include "framework/devices/HapticDevice.h"
#include "framework/geometry/DeformableMesh.h"
#include "framework/geometry/DrillableVolume.h"
#include "plugins/openigtlink/IGTLinkExporter.h"
#include "tests/support/BrainProbe.h"
#include "tests/support/TestSupport.h"

// Debian's libopenigtlink (1.11) leaks what it allocates to read a POLYDATA
// (igtl_polydata_alloc_info in PolyDataMessage::UnpackContent, never freed):
// the library's, not the exporter's. LeakSanitizer reads this hook.
extern "C" const char* __lsan_default_suppressions() { return "leak:igtl_polydata_alloc_info\n"; }

namespace trephine::test {
namespace {

const std::string kScene = R"(<Node name="root" units="mm">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="openigtlink"/>
  <Node name="patient">
    <VoxelSkull name="skull" file="phantom:skull?voxel=2" isovalue="400" drill="true"/>
    <TetraBrain name="brain" file="phantom:cube?cells=6&amp;size=20"/>
  </Node>
  <Node name="tool">
    <ScriptedDevice name="device" path="drill-in" target="@/patient/skull" direction="0 0 -1"
                    tipOffset="2.5" standoff="4" speed="20" depth="6" feedSpeed="4"
                    buttonTimes="0.3 1.3" rate="1000"/>
    <PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>
    <GodObjectProxy name="proxy" tool="@burr" target="@/patient/skull" sweep="cylinder" drillButton="1" rate="1000"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" damping="0.002" maxForce="3.3" rate="1000"/>
  </Node>
  <Node name="stream">
    <IGTLinkExporter name="slicer" port="0" force="@/tool/force" skull="@/patient/skull" brain="@/patient/brain"
                     imageInterval="0.2" rate="30"/>
  </Node>
</Node>)";

struct Received {
  std::vector<int16_t> volume;  // the client's copy of the skull
  int dims[3] = {0, 0, 0};
  int wholeImages = 0, partialImages = 0, polydata = 0, transforms = 0, sensors = 0, badCrc = 0;
  int slabs = 0, slabSlices = 0;  // the skull's slabs of whole slices, and the slices they held
  // Where the library places voxel (0, 0, 0) and the steps along i, j, k (RAS mm), from the IMAGE's
  // matrix, spacing and centre as 3D Slicer reads them.
  std::array<double, 3> firstVoxel{}, stepI{}, stepJ{}, stepK{};
  int coordinate = 0;
  int polygons = 0, points = 0;
  std::array<float, 3> firstPoint{};
  std::vector<std::vector<std::array<float, 3>>> surfaces;  // the points of every POLYDATA
  std::vector<int> polygonCounts;                           // the triangles of every POLYDATA
  float lastDevice[3] = {0, 0, 0};
};

void readAll(igtl::ClientSocket* socket, Received& r) {
  for (;;) {
    auto header = igtl::MessageHeader::New();
    header->InitPack();
    if (socket->Receive(header->GetPackPointer(), header->GetPackSize()) != header->GetPackSize()) return;
    header->Unpack();
    const std::string type = header->GetDeviceType();
    igtl::MessageBase::Pointer body;
    igtl::ImageMessage::Pointer image;
    igtl::PolyDataMessage::Pointer poly;
    igtl::TransformMessage::Pointer transform;
    if (type == "IMAGE")
      body = image = igtl::ImageMessage::New();
    else if (type == "POLYDATA")
      body = poly = igtl::PolyDataMessage::New();
    else if (type == "TRANSFORM")
      body = transform = igtl::TransformMessage::New();
    else if (type == "SENSOR")
      body = igtl::SensorMessage::New();
    else {
      socket->Skip(header->GetBodySizeToRead(), 0);
      continue;
    }
    body->SetMessageHeader(header);
    body->AllocatePack();
    if (socket->Receive(body->GetPackBodyPointer(), body->GetPackBodySize()) != body->GetPackBodySize()) return;
    if (body->Unpack(1) != igtl::MessageHeader::UNPACK_BODY) {
      ++r.badCrc;
      continue;
    }
    if (image) {
      int size[3], offset[3];
      image->GetDimensions(r.dims);
      image->GetSubVolume(size, offset);
      const bool whole = size[0] == r.dims[0] && size[1] == r.dims[1] && size[2] == r.dims[2];
      // The skull comes whole, or in slabs of whole slices that together
      // are (a large one), then as the blocks the drill changed.
      const bool slab = !whole && offset[0] == 0 && offset[1] == 0 && size[0] == r.dims[0] && size[1] == r.dims[1] &&
                        offset[2] == r.slabSlices;
      if (r.volume.empty()) r.volume.assign(size_t(r.dims[0]) * r.dims[1] * r.dims[2], 0);
      if (whole) {
        ++r.wholeImages;
        r.slabSlices = r.dims[2];
      } else if (slab && r.slabSlices < r.dims[2]) {
        ++r.slabs;
        r.slabSlices += size[2];
        if (r.slabSlices == r.dims[2]) ++r.wholeImages;
      } else {
        ++r.partialImages;
      }
      if (r.coordinate == 0) {
        r.coordinate = image->GetCoordinateSystem();
        igtl::Matrix4x4 m;
        image->GetMatrix(m);
        float spacing[3];
        image->GetSpacing(spacing);
        // The origin is the volume's centre: voxel 0 lies half the volume back along each axis.
        for (int c = 0; c < 3; ++c) {
          r.stepI[c] = m[c][0] * spacing[0];
          r.stepJ[c] = m[c][1] * spacing[1];
          r.stepK[c] = m[c][2] * spacing[2];
          r.firstVoxel[c] = m[c][3] - 0.5 * ((r.dims[0] - 1) * r.stepI[c] + (r.dims[1] - 1) * r.stepJ[c] +
                                             (r.dims[2] - 1) * r.stepK[c]);
        }
      }
      EXPECT_EQ(image->GetScalarType(), igtl::ImageMessage::TYPE_INT16);
      // The library leaves the scalars in the message's byte order, which it declares (as Slicer reads it).
      EXPECT_EQ(image->GetEndian(), igtl::ImageMessage::ENDIAN_BIG);
      const auto* bytes = static_cast<const unsigned char*>(image->GetScalarPointer());
      size_t n = 0;
      for (int k = 0; k < size[2]; ++k)
        for (int j = 0; j < size[1]; ++j)
          for (int i = 0; i < size[0]; ++i) {
            const size_t at = size_t(offset[0] + i) +
                              size_t(r.dims[0]) * (size_t(offset[1] + j) + size_t(r.dims[1]) * (offset[2] + k));
            r.volume[at] = static_cast<int16_t>((bytes[2 * n] << 8) | bytes[2 * n + 1]);
            ++n;
          }
    } else if (poly) {
      ++r.polydata;
      r.points = poly->GetPoints()->GetNumberOfPoints();
      r.polygons = static_cast<int>(poly->GetPolygons()->GetNumberOfCells());
      r.polygonCounts.push_back(r.polygons);
      poly->GetPoints()->GetPoint(0, r.firstPoint.data());
      auto& points = r.surfaces.emplace_back(size_t(r.points));
      for (int i = 0; i < r.points; ++i) poly->GetPoints()->GetPoint(unsigned(i), points[size_t(i)].data());
    } else if (transform) {
      ++r.transforms;
      if (std::strcmp(transform->GetDeviceName(), "TrephineDevice") == 0) {
        igtl::Matrix4x4 m;
        transform->GetMatrix(m);
        for (int c = 0; c < 3; ++c) r.lastDevice[c] = m[c][3];
      }
    } else {
      ++r.sensors;
    }
  }
}

// Runs `xml` in real time for `duration` with a client connected to its
// exporter (/stream/slicer) from the start; `inspect` sees the scene after the
// run, before it goes (which closes the server and ends the client's reading).
template <class Inspect, class Started = void (*)(int)>
Received runStreamed(
    const std::string& xml, double duration, Inspect&& inspect, Started started = [](int) {}) {
  SimulationOptions options;
  options.duration = duration;
  options.realtime = true;
  Diagnostics diagnostics;
  Received received;
  auto simulation = loadScene(xml, diagnostics, options);
  EXPECT_TRUE(simulation) << messages(diagnostics);
  if (!simulation) return received;
  const auto* exporter =
      dynamic_cast<const openigtlink::IGTLinkExporter*>(simulation->scene().findComponent("/stream/slicer"));
  EXPECT_NE(exporter, nullptr);
  if (!exporter) return received;
  auto socket = igtl::ClientSocket::New();
  EXPECT_EQ(socket->ConnectToServer("127.0.0.1", exporter->listeningPort()), 0);
  std::thread reader([&] { readAll(socket, received); });
  started(exporter->listeningPort());
  simulation->run();
  inspect(*simulation);
  simulation.reset();
  reader.join();
  return received;
}

TEST(IGTLinkExporterTest, ASlicerLikeClientRebuildsTheDrilledSkullAndGetsTheBrainPosesAndForce) {
  VoxelGrid grid;
  std::vector<int16_t> drilled;
  double removed = 0;
  TetMesh mesh;
  Vec3 device = Vec3::Zero();
  const Received received = runStreamed(kScene, 2.0, [&](const Simulation& simulation) {
    const auto* skull = dynamic_cast<const DrillableVolume*>(simulation.scene().findComponent("/patient/skull"));
    const auto* brain = dynamic_cast<const DeformableMesh*>(simulation.scene().findComponent("/patient/brain"));
    ASSERT_TRUE(skull && brain);
    grid = skull->voxelGrid();  // its codes go with the scene: copied
    drilled.assign(grid.codes, grid.codes + grid.voxelCount());
    removed = componentCounterAt(simulation, "/patient/skull", "voxels_removed");
    mesh = brain->mesh();
    device = dynamic_cast<const HapticDevice*>(simulation.scene().findComponent("/tool/device"))->state().pose.position;
  });
  EXPECT_EQ(received.badCrc, 0);
  EXPECT_EQ(received.wholeImages, 1) << "the whole skull once, when the client connected";
  EXPECT_GT(removed, 0) << "the burr drilled";
  EXPECT_GT(received.partialImages, 0) << "then the drilled blocks";
  EXPECT_EQ(received.dims[0], grid.nx);
  EXPECT_EQ(received.dims[2], grid.nz);
  // The scene's world is LPS; Slicer reads RAS: the IMAGE says RAS, and voxel
  // (0, 0, 0) and the voxel steps land where the scene has them, x and y negated.
  EXPECT_EQ(received.coordinate, igtl::ImageMessage::COORDINATE_RAS);
  const Vec3 firstLps = grid.corner + 0.5 * grid.spacing;
  for (int c = 0; c < 3; ++c) {
    const double flip = c < 2 ? -1.0 : 1.0;
    EXPECT_NEAR(received.firstVoxel[c], flip * firstLps[c], 1e-3) << "axis " << c;
    EXPECT_NEAR(received.stepI[c], c == 0 ? flip * grid.spacing[0] : 0.0, 1e-5);
    EXPECT_NEAR(received.stepJ[c], c == 1 ? flip * grid.spacing[1] : 0.0, 1e-5);
    EXPECT_NEAR(received.stepK[c], c == 2 ? grid.spacing[2] : 0.0, 1e-5);
  }
  // The first image with every sub-volume laid over it is the drilled skull, voxel for voxel.
  ASSERT_EQ(received.volume.size(), drilled.size());
  size_t differ = 0, firstDiffer = 0;
  for (size_t i = 0; i < drilled.size(); ++i)
    if (received.volume[i] != drilled[i] && differ++ == 0) firstDiffer = i;
  EXPECT_EQ(differ, 0u) << "first at " << firstDiffer << ": " << received.volume[firstDiffer] << " against "
                        << drilled[firstDiffer];
  // The brain's boundary (a rigid brain: sent once, at rest): its triangles and the nodes on them only.
  const TetTopology topology(mesh);
  std::set<int32_t> onBoundary;
  for (const BoundaryFace& f : topology.boundaryFaces())
    for (int c = 1; c <= 3; ++c) onBoundary.insert(mesh.tets[size_t(f.tet)][(f.face + c) % 4]);
  EXPECT_EQ(received.polydata, 1);
  EXPECT_EQ(received.points, static_cast<int>(onBoundary.size()));
  EXPECT_LT(onBoundary.size(), mesh.nodeCount()) << "the cube has nodes inside";
  EXPECT_EQ(received.polygons, static_cast<int>(topology.boundaryFaces().size()));
  const BoundaryFace& first = topology.boundaryFaces().front();
  EXPECT_NEAR(received.firstPoint[0], -mesh.nodes[size_t(mesh.tets[size_t(first.tet)][(first.face + 1) % 4])].x(), 1e-4)
      << "RAS: x negated";
  // Poses and the force at about 30 Hz for 2 s, two TRANSFORMs a frame.
  EXPECT_GT(received.sensors, 40);
  EXPECT_EQ(received.transforms, 2 * received.sensors);
  EXPECT_NEAR(received.lastDevice[2], device.z(), 1e-3);
  EXPECT_NEAR(received.lastDevice[0], -device.x(), 1e-3) << "RAS: x negated";
  EXPECT_NEAR(received.lastDevice[1], -device.y(), 1e-3) << "RAS: y negated";
}

// A cube of tissue on the TLED FEM, fixed at its base, pressed 4 mm by a probe.
const std::string kDeformingScene =
    R"(<Node name="root" units="mm">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  <RequiredPlugin name="openigtlink"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=6&amp;size=40" forceSpread="10"/>
    <TLEDForceField name="fem" mesh="@brain" dt="0.33e-3" massScaling="true" rate="1000" group="fem"/>
    <FixedConstraint name="base" fem="@fem" box="-100 -100 -100 100 100 -19"/>
  </Node>
  )" +
    test::brainProbeNode(R"(path="drill-in" center="0 0 0" standoff="3" speed="20" depth="4" feedSpeed="8")",
                         R"(sweep="line")") +
    R"(
  <Node name="stream">
    <IGTLinkExporter name="slicer" port="0" force="@/tool/force" brain="@/patient/brain" rate="30"/>
  </Node>
</Node>)";

TEST(IGTLinkExporterTest, ADeformingBrainsSurfaceIsSentAgainAsItMoves) {
  TetMesh rest;
  const Received received = runStreamed(kDeformingScene, 1.5, [&](const Simulation& simulation) {
    const auto* brain = dynamic_cast<const DeformableMesh*>(simulation.scene().findComponent("/patient/brain"));
    ASSERT_NE(brain, nullptr);
    rest = brain->mesh();
  });
  EXPECT_EQ(received.badCrc, 0);
  EXPECT_GT(received.polydata, 3) << "sent when the client connected, then as the cube moved";
  // The surface's points are the boundary's nodes in the order its faces first meet them.
  std::vector<int32_t> order, seen(rest.nodeCount(), 0);
  const TetTopology topology(rest);
  for (const BoundaryFace& f : topology.boundaryFaces())
    for (int c = 1; c <= 3; ++c) {
      const int32_t node = rest.tets[size_t(f.tet)][(f.face + c) % 4];
      if (!seen[size_t(node)]++) order.push_back(node);
    }
  // The first surface is the cube at rest; those sent after it show the dent under the probe.
  std::vector<double> largest;
  for (const auto& surface : received.surfaces) {
    ASSERT_EQ(surface.size(), order.size());
    double d = 0;
    for (size_t i = 0; i < order.size(); ++i)
      // The surface comes in RAS, the scene's LPS with x and y negated.
      d = std::max(d, (Vec3(-surface[i][0], -surface[i][1], surface[i][2]) - rest.nodes[size_t(order[i])]).norm());
    largest.push_back(d);
  }
  ASSERT_FALSE(largest.empty());
  EXPECT_LT(largest.front(), 1e-4) << "mm: at rest when the client connected";
  EXPECT_GT(*std::max_element(largest.begin(), largest.end()), 1.0) << "mm: the probe pressed the cube";
}

// Clients that come and go while the skull is drilled: each new one gets
// the skull in slabs of whole slices, 2 MB a tick for all of them, so the
// exporter's 30 Hz group keeps its deadlines (before, each new client cost
// the group a whole-skull IMAGE in the tick it came: 50 misses under churn
// with a CT), and a client that stays rebuilds the skull voxel for voxel.
TEST(IGTLinkExporterTest, ClientsThatComeAndGoGetTheSkullInSlabsWithinTheGroupsBudget) {
  std::string xml = kScene;
  xml.replace(xml.find("voxel=2"), 7, "voxel=1");  // 213 x 202 x 142 voxels: 12 MB of codes
  VoxelGrid grid;
  std::vector<int16_t> drilled;
  uint64_t misses = 0, calls = 0;
  double accepted = 0;
  std::atomic<bool> done{false};
  std::thread churn;
  const Received received = runStreamed(
      xml, 2.0,
      [&](const Simulation& simulation) {
        done = true;
        churn.join();
        const auto* skull = dynamic_cast<const DrillableVolume*>(simulation.scene().findComponent("/patient/skull"));
        ASSERT_TRUE(skull);
        grid = skull->voxelGrid();
        drilled.assign(grid.codes, grid.codes + grid.voxelCount());
        for (const RateGroup& g : simulation.scheduler().groups())
          if (std::abs(g.periodS - 1.0 / 30) < 1e-9) misses = g.deadlineMisses, calls = g.calls;
        accepted = componentCounterAt(simulation, "/stream/slicer", "clients_accepted");
      },
      [&](int port) {
        churn = std::thread([&, port] {
          // Three at a time, a new three every 150 ms, each gone after 100 ms.
          while (!done) {
            std::vector<igtl::ClientSocket::Pointer> sockets;
            for (int k = 0; k < 3; ++k) {
              sockets.push_back(igtl::ClientSocket::New());
              sockets.back()->ConnectToServer("127.0.0.1", port);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            for (auto& socket : sockets) socket->CloseSocket();
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
          }
        });
      });
  EXPECT_GT(received.slabs, 1) << "a skull of 12 MB goes in slabs";
  EXPECT_EQ(received.wholeImages, 1) << "which together are the whole skull, once";
  ASSERT_EQ(received.volume.size(), drilled.size());
  size_t differ = 0;
  for (size_t i = 0; i < drilled.size(); ++i) differ += received.volume[i] != drilled[i];
  EXPECT_EQ(differ, 0u) << "the client that stayed holds the drilled skull";
  EXPECT_GT(accepted, 20) << "clients came and went";
  EXPECT_GT(calls, kTimingChecked ? 50u : 10u);  // 60 in 2 s at 30 Hz; a sanitizer's are slower
  // A whole-skull IMAGE a new client cost 50 misses in 60 ticks; in slabs
  // none are the slabs' own, but the suite runs beside other tests on two
  // cores, where a tick now and then is late for reasons not the exporter's
  // (one in 60 was seen on a loaded machine): 1 in 20 still tells the two apart.
  if (kTimingChecked) {
    EXPECT_LE(misses, calls / 20) << "of " << calls << " ticks of the exporter's group";
  }
}

// A client that takes nothing it is sent (it never reads) is let go after
// `clientTimeout` behind (before, only once 256 MB waited for it): slow
// clients never hold the connections for good.
TEST(IGTLinkExporterTest, AClientThatDoesNotReadIsLetGoAfterTheTimeout) {
  std::string xml = kScene;
  xml.replace(xml.find("rate=\"30\"/>"), 11, "maxClients=\"2\" clientTimeout=\"0.3\" rate=\"30\"/>");
  xml.replace(xml.find("voxel=2"), 7, "voxel=1");  // 12 MB of skull: more than the sockets' buffers hold
  double slow = 0, refused = 0;
  std::vector<int> sleepers;
  const Received received = runStreamed(
      xml, 1.5,
      [&](const Simulation& simulation) {
        slow = componentCounterAt(simulation, "/stream/slicer", "clients_slow");
        refused = componentCounterAt(simulation, "/stream/slicer", "clients_refused");
      },
      [&](int port) {
        // One more client that never reads: with the reader, both connections taken.
        const int fd = socket(AF_INET, SOCK_STREAM, 0);
        const int small = 4096;
        setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
        sockaddr_in address{};
        address.sin_family = AF_INET;
        address.sin_port = htons(static_cast<uint16_t>(port));
        inet_pton(AF_INET, "127.0.0.1", &address.sin_addr);
        EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
        sleepers.push_back(fd);
      });
  for (const int fd : sleepers) close(fd);
  EXPECT_GE(slow, 1) << "the client that never read was let go";
  EXPECT_EQ(refused, 0);
  EXPECT_EQ(received.wholeImages, 1) << "the reader was served throughout";
  EXPECT_GT(received.sensors, kTimingChecked ? 30 : 10) << "45 in 1.5 s at 30 Hz; a sanitizer's are fewer";
}

// The tumour resection on a coarser phantom, streamed: once the aspirator
// removed tissue, the POLYDATA's surface is what remains (the cavity's walls
// with it), as many triangles as the brain's boundary then has; before,
// every surface sent was the first boundary.
TEST(IGTLinkExporterTest, AResectedBrainsSurfaceShowsTheCavity) {
  std::string xml = readFile(sourceDir() / "scenes" / "resection.xml");
  xml.replace(xml.find("tets=22000"), std::string("tets=22000").size(), "tets=5000");
  // The aspirator feeds straight into the tumour (it removes within a second).
  const size_t device = xml.find(R"(<ScriptedDevice name="device" path="waypoints")");
  xml.replace(device, xml.find("/>", device) + 2 - device,
              R"(<ScriptedDevice name="device" path="drill-in" target="@/patient/brain" direction="0 0 -1"
                    center="25 10 0" tipOffset="1.2" standoff="2" speed="20" depth="5" feedSpeed="2" rate="1000"/>)");
  xml.insert(xml.find("<RequiredPlugin"), R"(<RequiredPlugin name="openigtlink"/>
  )");
  xml.insert(xml.rfind("</Node>"), R"(<Node name="stream">
    <IGTLinkExporter name="slicer" port="0" brain="@/patient/brain" rate="30" surfaceInterval="0.1"/>
  </Node>
)");
  double firstBoundary = 0, removed = 0, boundaryNow = 0;
  const Received received = runStreamed(xml, 4.0, [&](const Simulation& simulation) {
    firstBoundary = componentCounterAt(simulation, "/patient/brain", "boundary_faces");
    removed = componentCounterAt(simulation, "/patient/brain", "removed_tetrahedra");
    boundaryNow = componentCounterAt(simulation, "/patient/brain", "boundary_faces_now");
  });
  ASSERT_GT(removed, 0.0) << "the aspirator removed nothing in 4 s";
  ASSERT_FALSE(received.polygonCounts.empty());
  EXPECT_EQ(received.polygonCounts.front(), int(firstBoundary));  // at rest when the client came
  EXPECT_NE(boundaryNow, firstBoundary);
  // A surface with the cavity went out: one of those sent has the boundary's count now.
  EXPECT_NE(std::find(received.polygonCounts.begin(), received.polygonCounts.end(), int(boundaryNow)),
            received.polygonCounts.end());
}

}  // namespace
}  // namespace trephine::test
