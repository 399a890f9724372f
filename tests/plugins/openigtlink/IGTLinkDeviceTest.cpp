// IGTLinkDevice in a running scene, driven by clients built on Debian's
// libopenigtlink (as 3D Slicer and PLUS are): a tracker's TRANSFORMs at
// 200 Hz press a sphere into a plane and every haptic frame after the first
// pose sends the spring's force back as a SENSOR in newtons; buttons come as
// STRING messages; clients that break the protocol are cut off while the
// others go on; more clients than allowed are refused; the server listens on
// loopback only.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <igtlClientSocket.h>
#include <igtlSensorMessage.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>
#include <igtl_unit.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

#include "plugins/openigtlink/IGTLinkDevice.h"
#include "tests/plugins/openigtlink/TrackerMessages.h"
#include "tests/support/TestSupport.h"

namespace trephine::test {
namespace {

using openigtlink::IGTLinkDevice;

std::string pressScene(const std::string& attributes = "") {
  return R"(<Node name="root" units="mm">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="openigtlink"/>
  <Node name="patient"><AnalyticPlane name="plane" point="0 0 0" normal="0 0 1"/></Node>
  <Node name="tool">
    <IGTLinkDevice name="device" port="0" transformName="Tool" forceName="Force" )" +
         attributes + R"( rate="1000"/>
    <SphereTool name="burr" radius="2.5" device="@device"/>
    <SpringForce name="force" tool="@burr" target="@/patient/plane" stiffness="2.0" damping="0" maxForce="3.3"
                 rate="1000"/>
  </Node>
</Node>)";
}

struct Loaded {
  std::unique_ptr<Simulation> simulation;
  int port = 0;
};

Loaded loadRealtime(const std::string& xml, double duration) {
  SimulationOptions options;
  options.duration = duration;
  options.realtime = true;
  Diagnostics diagnostics;
  Loaded loaded;
  loaded.simulation = loadScene(xml, diagnostics, options);
  EXPECT_TRUE(loaded.simulation) << messages(diagnostics);
  if (!loaded.simulation) return loaded;
  const auto* device = dynamic_cast<const IGTLinkDevice*>(loaded.simulation->scene().findComponent("/tool/device"));
  EXPECT_NE(device, nullptr);
  if (device) loaded.port = device->listeningPort();
  return loaded;
}

// A tracker: sends TRANSFORMs named "Tool" at `hz` for `seconds`, and reads every message that comes back.
struct Tracker {
  igtl::ClientSocket::Pointer socket = igtl::ClientSocket::New();
  std::vector<std::array<double, 3>> forces;  // the SENSORs named Force, in order
  std::vector<double> stamps;                 // their timestamps (s)
  int badSensors = 0;
  std::thread reader;

  bool connect(int port) { return socket->ConnectToServer("127.0.0.1", port) == 0; }
  void startReading() {
    reader = std::thread([this] {
      for (;;) {
        const igtltest::ReceivedSensor received = igtltest::receiveSensor(*socket);
        if (!received.message) return;
        const auto& sensor = received.message;
        igtl_unit_data unit;
        if (!received.unpacked || sensor->GetLength() != 3 || std::strcmp(sensor->GetDeviceName(), "Force") != 0 ||
            igtl_unit_unpack(sensor->GetUnit(), &unit) != 1 || unit.unit[0] != IGTL_UNIT_SI_DERIVED_NEWTON) {
          ++badSensors;
          continue;
        }
        forces.push_back({sensor->GetValue(0), sensor->GetValue(1), sensor->GetValue(2)});
        igtl::TimeStamp::Pointer stamp = igtl::TimeStamp::New();
        sensor->GetTimeStamp(stamp);
        stamps.push_back(stamp->GetTimeStamp());
      }
    });
  }
  void sendPose(float x, float y, float z) { igtltest::sendPose(*socket, "Tool", x, y, z); }
  // Sends the pose every 5 ms (200 Hz), `count` times at most, while the
  // simulation runs to its end in this thread; `afterEach(i)` after the i-th
  // pose (a button, say), and `beside(done)` in a thread of its own meanwhile
  // (other clients; `done` once the run has ended).
  void sendWhileRunning(Simulation& simulation, float x, float y, float z, int count,
                        const std::function<void(int)>& afterEach = {},
                        const std::function<void(const std::atomic<bool>&)>& beside = {}) {
    std::atomic<bool> done{false};
    std::thread sender([&] {
      for (int i = 0; !done && i < count; ++i) {
        sendPose(x, y, z);
        if (afterEach) afterEach(i);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    });
    std::thread other;
    if (beside) other = std::thread([&] { beside(done); });
    simulation.run();
    done = true;
    sender.join();
    if (other.joinable()) other.join();
  }
  void sendString(const char* name, const char* text) {
    auto message = igtl::StringMessage::New();
    message->SetDeviceName(name);
    message->SetString(text);
    message->Pack();
    socket->Send(message->GetPackPointer(), message->GetPackSize());
  }
  void finish() {
    if (reader.joinable()) reader.join();
    socket->CloseSocket();
  }
};

TEST(IGTLinkDeviceTest, ATrackersPosesPressASphereAndEveryFrameAfterTheFirstSendsTheForceBack) {
  Loaded loaded = loadRealtime(pressScene("buttonsName=\"Pedal\""), 0.6);
  ASSERT_TRUE(loaded.simulation);
  ASSERT_GT(loaded.port, 0);
  Tracker tracker;
  ASSERT_TRUE(tracker.connect(loaded.port));
  tracker.startReading();
  // Pressing 1 mm (the sphere's centre at 1.5 mm over the plane); the pedal down after 0.3 s.
  tracker.sendWhileRunning(*loaded.simulation, 3.0f, 0.0f, 1.5f, 400, [&](int i) {
    if (i == 60) tracker.sendString("Pedal", "1");
  });
  const auto& simulation = *loaded.simulation;
  const uint64_t transforms =
      static_cast<uint64_t>(componentCounterAt(simulation, "/tool/device", "transforms_received"));
  const double sensorsSent = componentCounterAt(simulation, "/tool/device", "sensors_sent");
  const double samples = componentCounterAt(simulation, "/tool/device", "samples");
  const auto* device = dynamic_cast<const HapticDevice*>(simulation.scene().findComponent("/tool/device"));
  ASSERT_NE(device, nullptr);
  EXPECT_EQ(device->state().buttons, 1u) << "the pedal's STRING";
  EXPECT_EQ(componentCounterAt(simulation, "/tool/device", "button_messages"), 1);
  // The server stops when the run's outputs are written (the client's reader ends), and its figures stay for
  // the summary.
  TempDir out;
  loaded.simulation->writeOutputs(out.path());
  tracker.finish();
  EXPECT_EQ(componentCounterAt(simulation, "/tool/device", "transforms_received"), static_cast<double>(transforms));
  EXPECT_NE(readFile(out / "summary.json").find("\"transforms_received\""), std::string::npos);

  EXPECT_EQ(tracker.badSensors, 0);
  EXPECT_GT(transforms, 50u);
  // Every frame from the first pose on sent its force, and the client read each one.
  EXPECT_EQ(static_cast<double>(tracker.forces.size()), sensorsSent);
  EXPECT_EQ(sensorsSent, samples) << "one SENSOR per frame after the first pose";
  ASSERT_GT(tracker.forces.size(), 100u);
  for (const auto& f : tracker.forces) {
    EXPECT_EQ(f[0], 0.0);
    EXPECT_NEAR(f[2], 2.0, 1e-5) << "k times 1 mm (the pose in float32)";
  }
  for (size_t i = 1; i < tracker.stamps.size(); ++i) EXPECT_GT(tracker.stamps[i], tracker.stamps[i - 1]);
  if (!kTimingChecked) return;
  EXPECT_GT(transforms, 100u) << "200 Hz for most of 0.6 s";
  EXPECT_GT(sensorsSent, 500) << "a frame at 1 kHz for most of 0.6 s";
}

// Connects a raw TCP client to the server.
int rawClient(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  inet_pton(AF_INET, "127.0.0.1", &address.sin_addr);
  EXPECT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  return fd;
}

TEST(IGTLinkDeviceTest, ClientsThatBreakTheProtocolAreCutOffAndTheOthersGoOn) {
  Loaded loaded = loadRealtime(pressScene("maxClients=\"3\""), 0.8);
  ASSERT_TRUE(loaded.simulation);
  Tracker tracker;
  ASSERT_TRUE(tracker.connect(loaded.port));
  tracker.startReading();
  tracker.sendWhileRunning(*loaded.simulation, 0.0f, 0.0f, 1.5f, 400, {}, [&](const std::atomic<bool>&) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    // Garbage: not a header.
    int fd = rawClient(loaded.port);
    const std::vector<unsigned char> junk(200, 0xAB);
    EXPECT_EQ(send(fd, junk.data(), junk.size(), MSG_NOSIGNAL), 200);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // each cut off before the next comes
    // A TRANSFORM whose body does not match its CRC.
    auto message = igtl::TransformMessage::New();
    message->SetDeviceName("Tool");
    message->Pack();
    std::vector<unsigned char> bytes(static_cast<unsigned char*>(message->GetPackPointer()),
                                     static_cast<unsigned char*>(message->GetPackPointer()) + message->GetPackSize());
    bytes.back() ^= 0x55;
    const int crcClient = rawClient(loaded.port);
    EXPECT_EQ(send(crcClient, bytes.data(), bytes.size(), MSG_NOSIGNAL), static_cast<ssize_t>(bytes.size()));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    // A header announcing a TRANSFORM of a gigabyte.
    const int hugeClient = rawClient(loaded.port);
    bytes.resize(58);
    for (int i = 42; i < 50; ++i) bytes[i] = i == 45 ? 0x40 : 0;
    EXPECT_EQ(send(hugeClient, bytes.data(), 58, MSG_NOSIGNAL), 58);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    // Three clients at once fill the server (the tracker and two that stay); the next is refused.
    const int stay1 = rawClient(loaded.port), stay2 = rawClient(loaded.port);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const int refused = rawClient(loaded.port);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    char c;
    EXPECT_EQ(recv(refused, &c, 1, 0), 0) << "closed by the server";
    for (const int f : {fd, crcClient, hugeClient, stay1, stay2, refused}) close(f);
  });
  const auto count = [&](const char* name) { return componentCounterAt(*loaded.simulation, "/tool/device", name); };
  EXPECT_EQ(count("clients_broken"), 3);
  EXPECT_EQ(count("clients_refused"), 1);
  EXPECT_EQ(count("rejected_non_finite"), 0);
  loaded.simulation.reset();
  tracker.finish();
  ASSERT_GT(tracker.forces.size(), 100u) << "the tracker was served throughout";
  EXPECT_NEAR(tracker.forces.back()[2], 2.0, 1e-5);
}

// Before, one far-away first TRANSFORM from any local client locked the
// device for the run (every real pose after it rejected as a jump), and any
// client's TRANSFORM named Tool drove it. Now a pose beyond the workspace is
// never taken, and the first client whose pose is taken is the device's:
// another's are counted and ignored.
TEST(IGTLinkDeviceTest, AStrayFarPoseAndASecondClientNeverDriveTheDevice) {
  Loaded loaded = loadRealtime(pressScene(), 0.8);
  ASSERT_TRUE(loaded.simulation);
  Tracker stray, tracker, intruder;
  ASSERT_TRUE(stray.connect(loaded.port));
  stray.sendPose(5000.0f, 0.0f, 0.0f);  // 5 m away, before the tracker's first pose
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  ASSERT_TRUE(tracker.connect(loaded.port));
  tracker.startReading();
  // 1 mm into the plane: 2 N.
  tracker.sendWhileRunning(*loaded.simulation, 0.0f, 0.0f, 1.5f, 400, {}, [&](const std::atomic<bool>& done) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    ASSERT_TRUE(intruder.connect(loaded.port));
    for (int i = 0; !done && i < 100; ++i) {
      intruder.sendPose(0.0f, 0.0f, 0.5f);  // 2 mm in: would be 4 N, clamped to 3.3
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
    }
  });
  const auto count = [&](const char* name) { return componentCounterAt(*loaded.simulation, "/tool/device", name); };
  EXPECT_EQ(count("poses_outside_workspace"), 1);
  EXPECT_GT(count("poses_other_clients"), 20) << "the intruder's poses, ignored";
  EXPECT_EQ(count("rejected_jump"), 0) << "the stray pose never became the hand's place";
  loaded.simulation.reset();
  tracker.finish();
  stray.finish();
  intruder.finish();
  ASSERT_GT(tracker.forces.size(), 100u);
  size_t afterIntruder = 0;
  for (size_t i = tracker.forces.size() / 2; i < tracker.forces.size(); ++i) {
    EXPECT_NEAR(tracker.forces[i][2], 2.0, 1e-5) << "the tracker's own 2 N, whatever the intruder sends";
    ++afterIntruder;
  }
  EXPECT_GT(afterIntruder, 50u);
}

// frame="RAS": a pose from 3D Slicer's patient frame is turned into the
// scene's LPS (x and y negated) and the force goes back in RAS.
TEST(IGTLinkDeviceTest, APoseInSlicersRasIsTurnedIntoTheScenesLps) {
  Loaded loaded = loadRealtime(pressScene("frame=\"RAS\""), 0.4);
  ASSERT_TRUE(loaded.simulation);
  Tracker tracker;
  ASSERT_TRUE(tracker.connect(loaded.port));
  tracker.startReading();
  tracker.sendWhileRunning(*loaded.simulation, 3.0f, 2.0f, 1.5f, 200);
  const auto* device = dynamic_cast<const IGTLinkDevice*>(loaded.simulation->scene().findComponent("/tool/device"));
  ASSERT_NE(device, nullptr);
  EXPECT_LT((device->state().pose.position - Vec3(-3, -2, 1.5)).norm(), 1e-5);
  loaded.simulation.reset();
  tracker.finish();
  ASSERT_GT(tracker.forces.size(), 50u);
  EXPECT_NEAR(tracker.forces.back()[2], 2.0, 1e-5) << "up, whichever frame";
}

// `client` names the one client to hear: a tracker from another address
// drives nothing (its poses are counted), and no force is sent.
TEST(IGTLinkDeviceTest, OnlyTheClientNamedDrivesTheDevice) {
  Loaded loaded = loadRealtime(pressScene("client=\"127.0.0.2\""), 0.4);
  ASSERT_TRUE(loaded.simulation);
  Tracker tracker;
  ASSERT_TRUE(tracker.connect(loaded.port));
  tracker.startReading();
  tracker.sendWhileRunning(*loaded.simulation, 0.0f, 0.0f, 1.5f, 200);
  const auto count = [&](const char* name) { return componentCounterAt(*loaded.simulation, "/tool/device", name); };
  EXPECT_GT(count("poses_other_clients"), 20);
  EXPECT_EQ(count("transforms_received"), 0);
  loaded.simulation.reset();
  tracker.finish();
  EXPECT_TRUE(tracker.forces.empty()) << "nothing drives it, so no force is sent";
}

// Clients that hold a connection without sending anything whole: one stopped
// mid-message is let go after `clientTimeout`; with every connection taken,
// one none of whose messages was taken (it sent nothing, or only a pose
// beyond the workspace) makes room for a tracker that comes later.
TEST(IGTLinkDeviceTest, AClientStoppedMidMessageOrHoldingASlotIsLetGo) {
  Loaded loaded = loadRealtime(pressScene("maxClients=\"2\" clientTimeout=\"0.2\""), 1.2);
  ASSERT_TRUE(loaded.simulation);
  const int stalled = rawClient(loaded.port);
  const unsigned char half[20] = {0, 1, 'T', 'R', 'A', 'N', 'S'};
  EXPECT_EQ(send(stalled, half, sizeof half, MSG_NOSIGNAL), 20);
  // Connects and sends one pose that is never taken (beyond the workspace), then nothing.
  Tracker holdingTracker;
  ASSERT_TRUE(holdingTracker.connect(loaded.port));
  holdingTracker.sendPose(5000.0f, 0.0f, 0.0f);
  Tracker tracker;
  std::atomic<bool> done{false};
  int filler = -1;
  std::thread late([&] {
    // The stalled one is gone by now; another that sends nothing takes its place.
    std::this_thread::sleep_for(std::chrono::milliseconds(350));
    filler = rawClient(loaded.port);
    std::this_thread::sleep_for(std::chrono::milliseconds(350));
    ASSERT_TRUE(tracker.connect(loaded.port));
    tracker.startReading();
    for (int i = 0; !done && i < 200; ++i) {
      tracker.sendPose(0.0f, 0.0f, 1.5f);
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
    }
  });
  loaded.simulation->run();
  done = true;
  late.join();
  const auto count = [&](const char* name) { return componentCounterAt(*loaded.simulation, "/tool/device", name); };
  EXPECT_EQ(count("clients_stalled"), 1);
  EXPECT_EQ(count("clients_idle"), 1);
  EXPECT_EQ(count("clients_refused"), 0);
  loaded.simulation.reset();
  tracker.finish();
  EXPECT_GT(tracker.forces.size(), 50u) << "the late tracker was served";
  close(stalled);
  holdingTracker.finish();
  close(filler);
}

TEST(IGTLinkDeviceTest, BadFieldsAreLoadErrorsThatSayWhatWasExpected) {
  for (const auto& [attributes, expected] :
       std::vector<std::pair<std::string, std::string>>{{"host=\"localhost\"", "dotted IPv4"},
                                                        {"buttonsName=\"APedalNameLongerThanTwenty\"", "20-byte"},
                                                        {"maxClients=\"0\"", "maxClients"},
                                                        {"client=\"localhost\"", "not HOST or HOST:PORT"},
                                                        {"client=\"127.0.0.1:0\"", "not HOST or HOST:PORT"},
                                                        {"workspace=\"0\"", "workspace"}}) {
    expectLoadError(pressScene(attributes), expected, attributes);
  }
  // A port another server holds: the load says which and why.
  Loaded holder = loadRealtime(pressScene(), 1.0);
  ASSERT_GT(holder.port, 0);
  std::string xml = pressScene();
  xml.replace(xml.find("port=\"0\""), 8, "port=\"" + std::to_string(holder.port) + "\"");
  SimulationOptions realtime;
  realtime.realtime = true;
  Diagnostics second;
  EXPECT_FALSE(loadScene(xml, second, realtime));
  EXPECT_NE(messages(second).find("127.0.0.1:" + std::to_string(holder.port)), std::string::npos) << messages(second);
}

TEST(IGTLinkDeviceTest, InVirtualTimeTheLoadWarnsAndNoServerListens) {
  Diagnostics diagnostics;
  auto simulation = loadScene(pressScene(), diagnostics);
  ASSERT_TRUE(simulation) << messages(diagnostics);
  EXPECT_NE(messages(diagnostics).find("--realtime"), std::string::npos) << messages(diagnostics);
  EXPECT_EQ(dynamic_cast<const IGTLinkDevice*>(simulation->scene().findComponent("/tool/device"))->listeningPort(), 0);
}

}  // namespace
}  // namespace trephine::test
