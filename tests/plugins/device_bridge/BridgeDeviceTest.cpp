// BridgeDevice, the simulation's end of the device bridge, driven in real
// time by a device program written on the C code alone (FakeBridgePeer):
// a pose pressed 1 mm into a plane comes back as the spring's 2 N over both
// transports and paces the haptic frames; a device that goes quiet gets a
// force that ramps to zero at the watchdog's slope and a logged event, and is
// taken where it is when it comes back; hostile packets are dropped and
// counted by what is wrong with them; the force sent is limited.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <thread>

#include "FakeBridgePeer.h"
#include "framework/logs/EventLog.h"
#include "tests/support/TestSupport.h"

namespace trephine::test {
namespace {

constexpr double kStiffness = 2.0;               // N/mm, the scene's spring
constexpr double kTimeout = 0.02, kRamp = 0.02;  // s, BridgeDevice's defaults

// A sphere of 2.5 mm on the bridged device over the plane z = 0; the spring has no damping, so
// a device held still at height z (mm) is pushed up with k (2.5 - z) N.
std::string pressScene(const std::string& bridgeAttributes) {
  return R"(<Node name="root" units="mm">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="device_bridge"/>
  <Node name="patient"><AnalyticPlane name="plane" point="0 0 0" normal="0 0 1"/></Node>
  <Node name="tool">
    <BridgeDevice name="device" )" +
         bridgeAttributes + R"( rate="1000"/>
    <SphereTool name="burr" radius="2.5" device="@device"/>
    <SpringForce name="force" tool="@burr" target="@/patient/plane" stiffness="2.0" damping="0" maxForce="3.3"
                 rate="1000"/>
  </Node>
</Node>)";
}

trephine_bridge_pose poseAt(double x, double z) {
  trephine_bridge_pose pose{};
  pose.position_mm[0] = x;
  pose.position_mm[2] = z;
  pose.orientation_wxyz[0] = 1;
  return pose;
}

std::unique_ptr<Simulation> loadRealtime(const std::string& xml, double duration) {
  SimulationOptions options;
  options.duration = duration;
  options.realtime = true;
  Diagnostics diagnostics;
  auto simulation = loadScene(xml, diagnostics, options);
  EXPECT_TRUE(simulation) << messages(diagnostics);
  return simulation;
}

double norm(const double f[3]) { return std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]); }

struct Transport {
  const char* name;
  bool udp;
};

class BridgeTransportTest : public ::testing::TestWithParam<Transport> {};

TEST_P(BridgeTransportTest, APosePressedIntoAPlaneComesBackAsTheSpringsForceAndPacesTheFrames) {
  const PeerLink link = GetParam().udp ? PeerLink::udp() : PeerLink::sharedMemory("press");
  auto simulation = loadRealtime(pressScene(link.attributes()), 0.6);
  ASSERT_TRUE(simulation);
  FakeDevice device(link, [](double) { return poseAt(3.0, 1.5); });  // 1 mm deep
  device.start();
  simulation->run();
  const auto forces = device.stop();
  const std::vector<uint64_t> sent = device.sentAt();

  // Past the watchdog's ramp in from the first pose, every force is k times the depth, straight up.
  ASSERT_GT(forces.size(), 100u);
  size_t checked = 0;
  std::vector<double> roundTripsUs;
  for (const auto& r : forces) {
    ASSERT_GE(r.force.answered_sequence, 1u);
    ASSERT_LE(r.force.answered_sequence, sent.size());
    // The force names the pose it answers by its sequence and its time.
    EXPECT_EQ(r.force.answered_device_time_ns, sent[r.force.answered_sequence - 1]);
    roundTripsUs.push_back(static_cast<double>(r.atNs - sent[r.force.answered_sequence - 1]) * 1e-3);
    if (r.atNs < device.startNs() + 100'000'000) continue;
    EXPECT_NEAR(r.force.force_n[2], kStiffness * 1.0, 1e-9);
    EXPECT_EQ(r.force.force_n[0], 0.0);
    EXPECT_EQ(r.force.flags, 0u);
    ++checked;
  }
  EXPECT_GT(checked, 50u);
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "poses_malformed"), 0);
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "poses_foreign"), 0);
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "watchdog_trips"), 0);
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "rejected_jump"), 0);
  if (!kTimingChecked) return;
  EXPECT_GT(checked, 300u);
  std::nth_element(roundTripsUs.begin(), roundTripsUs.begin() + roundTripsUs.size() / 2, roundTripsUs.end());
  // Paced by the device, a frame starts when its pose comes: the median
  // round trip is a small part of the 1 ms frame (CI machines are noisy).
  EXPECT_LT(roundTripsUs[roundTripsUs.size() / 2], 500.0);
  const RateGroup& haptic = simulation->scheduler().groups().front();
  EXPECT_GT(haptic.pacedFrames, haptic.calls * 8 / 10) << "frames started by the device's poses";
  EXPECT_GT(componentCounterAt(*simulation, "/tool/device", "poses_received"), 400);
}

INSTANTIATE_TEST_SUITE_P(BothTransports, BridgeTransportTest,
                         ::testing::Values(Transport{"shm", false}, Transport{"udp", true}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(BridgeDeviceTest, AQuietDeviceFeelsTheForceRampToZeroAndIsTakenWhereItIsWhenItReturns) {
  const PeerLink link = PeerLink::sharedMemory("quiet");
  auto simulation = loadRealtime(pressScene(link.attributes()), 0.7);
  ASSERT_TRUE(simulation);
  // Pressing 1 mm for 0.25 s; quiet until 0.4 s; back 8 mm to the side, pressing 0.5 mm.
  FakeDevice device(
      link, [](double t) { return t < 0.3 ? poseAt(0, 1.5) : poseAt(8, 2.0); },
      [](double t) { return t < 0.25 || t >= 0.4; });
  device.start();
  simulation->run();
  const auto forces = device.stop();
  const std::vector<uint64_t> sent = device.sentAt();
  size_t gap = 0;
  for (size_t i = 1; i < sent.size(); ++i)
    if (sent[i] - sent[i - 1] > 50'000'000) gap = i;
  ASSERT_GT(gap, 0u) << "the device was quiet";
  const uint64_t lastBefore = sent[gap - 1], firstAfter = sent[gap];

  size_t zeroed = 0, ramped = 0;
  const trephine_bridge_force* previous = nullptr;
  for (const auto& r : forces) {
    const trephine_bridge_force& f = r.force;
    const double magnitude = norm(f.force_n);
    ASSERT_TRUE(std::isfinite(magnitude));
    ASSERT_LE(magnitude, 3.3);
    if (previous && r.atNs > device.startNs() + 100'000'000) {
      // No step beyond the ramp's slope (full force, 2 N, over kRamp) in the
      // time between the two. The gain moves with the time between the
      // frames' starts, the stamps are taken when each force is sent: 0.5 ms
      // is allowed for the difference.
      const double dt = static_cast<double>(f.simulation_time_ns - previous->simulation_time_ns) * 1e-9;
      const double step = std::abs(norm(f.force_n) - norm(previous->force_n));
      EXPECT_LE(step, kStiffness * 1.0 * (dt + 0.0005) / kRamp + 1e-9)
          << "at " << (r.atNs - device.startNs()) * 1e-9 << " s";
    }
    previous = &f;
    const bool quiet = f.simulation_time_ns > lastBefore && f.simulation_time_ns < firstAfter;
    if (quiet && f.simulation_time_ns > lastBefore + static_cast<uint64_t>((kTimeout + kRamp + 0.003) * 1e9)) {
      EXPECT_EQ(magnitude, 0.0) << "zero within the timeout and the ramp";
      EXPECT_TRUE(f.flags & TREPHINE_BRIDGE_FORCE_WATCHDOG);
      ++zeroed;
    } else if (quiet && magnitude > 0 && magnitude < 1.99) {
      ++ramped;
    }
  }
  EXPECT_GT(zeroed, 50u);
  EXPECT_GT(ramped, 5u) << "ramped down, not cut";
  // Back: the force of the new place (k times 0.5 mm), ramped in.
  ASSERT_FALSE(forces.empty());
  EXPECT_NEAR(forces.back().force.force_n[2], kStiffness * 0.5, 1e-9);

  // Under a sanitizer a thread stalled past the 20 ms timeout is a quiet
  // spell too (seen once in a full run): there, at least the one planned.
  const double trips = componentCounterAt(*simulation, "/tool/device", "watchdog_trips");
  if (kTimingChecked)
    EXPECT_EQ(trips, 1);
  else
    EXPECT_GE(trips, 1);
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "rejected_jump"), 0) << "taken where it is";
  int tripped = 0, recovered = 0;
  const EventLog& events = simulation->events();
  for (size_t i = 0; i < events.size(); ++i)
    if (std::string(events[i].kind) == "bridge_watchdog") {
      tripped += std::string(events[i].detail) == "tripped";
      recovered += std::string(events[i].detail) == "recovered";
    }
  EXPECT_EQ(tripped, kTimingChecked ? 1 : int(trips));
  EXPECT_EQ(recovered, tripped);
}

// Bytes of a valid pose with one thing changed.
std::vector<unsigned char> poseBytes(uint64_t session, uint64_t sequence, void (*spoil)(unsigned char*) = nullptr) {
  trephine_bridge_pose pose = poseAt(3.0, 1.5);
  pose.session = session;
  pose.sequence = sequence;
  std::vector<unsigned char> bytes(TREPHINE_BRIDGE_POSE_SIZE);
  EXPECT_EQ(trephine_bridge_encode_pose(&pose, bytes.data()), TREPHINE_BRIDGE_OK);
  if (spoil) spoil(bytes.data());
  return bytes;
}

TEST(BridgeDeviceTest, HostilePacketsAreDroppedAndCountedByWhatIsWrongWithThem) {
  const PeerLink link = PeerLink::udp();
  auto simulation = loadRealtime(pressScene(link.attributes()), 0.8);
  ASSERT_TRUE(simulation);
  FakeDevice device(link, [](double) { return poseAt(3.0, 1.5); });
  std::thread attacker([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));  // the device is the peer by now
    const auto spoilMagic = [](unsigned char* b) { b[0] = 'X'; };
    const auto spoilVersion = [](unsigned char* b) { b[4] = 9; };
    const auto spoilKind = [](unsigned char* b) { b[6] = 2; };
    const auto spoilValue = [](unsigned char* b) { std::memset(b + 24, 0xff, 8); };  // x is a NaN
    const auto send = [&](const std::vector<unsigned char>& bytes, size_t size) {
      device.sendRaw(bytes.data(), size);
      std::this_thread::sleep_for(std::chrono::microseconds(300));
    };
    const uint64_t session = device.session();
    for (int i = 0; i < 3; ++i) send(poseBytes(session, 1u << 20, spoilMagic), TREPHINE_BRIDGE_POSE_SIZE);
    for (int i = 0; i < 4; ++i) send(poseBytes(session, 1u << 20, spoilVersion), TREPHINE_BRIDGE_POSE_SIZE);
    for (int i = 0; i < 5; ++i) send(poseBytes(session, 1u << 20), TREPHINE_BRIDGE_POSE_SIZE - 1);
    for (int i = 0; i < 6; ++i) send(poseBytes(session, 1u << 20, spoilValue), TREPHINE_BRIDGE_POSE_SIZE);
    for (int i = 0; i < 2; ++i) send(poseBytes(session, 1u << 20, spoilKind), TREPHINE_BRIDGE_POSE_SIZE);
    for (int i = 0; i < 7; ++i) send(poseBytes(session, 1), TREPHINE_BRIDGE_POSE_SIZE);  // long past: stale
    // Far ahead in the device's own session: more than the time since explains.
    for (int i = 0; i < 4; ++i) send(poseBytes(session, uint64_t(1) << 62), TREPHINE_BRIDGE_POSE_SIZE);
    // A stranger: valid poses from another socket, then a flood.
    trephine_bridge_address local{}, simulationAddress{};
    trephine_bridge_address_parse("127.0.0.1", 0, &local);
    trephine_bridge_address_parse("127.0.0.1", link.simulationPort, &simulationAddress);
    trephine_bridge_udp* stranger = trephine_bridge_udp_open(&local, nullptr);
    ASSERT_NE(stranger, nullptr);
    for (int i = 0; i < 10; ++i) {
      const auto bytes = poseBytes(trephine_bridge_new_session(), 1u << 24);
      trephine_bridge_udp_send(stranger, &simulationAddress, bytes.data(), bytes.size());
      std::this_thread::sleep_for(std::chrono::microseconds(300));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const unsigned char junk[1400] = {};
    for (int i = 0; i < 20000; ++i) trephine_bridge_udp_send(stranger, &simulationAddress, junk, sizeof junk);
    trephine_bridge_udp_close(stranger);
  });
  device.start();
  simulation->run();
  attacker.join();
  const auto forces = device.stop();

  const auto count = [&](const char* name) { return componentCounterAt(*simulation, "/tool/device", name); };
  EXPECT_EQ(count("poses_malformed_magic"), 3);
  EXPECT_EQ(count("poses_wrong_version"), 4);
  EXPECT_EQ(count("poses_malformed_size"), 5);
  EXPECT_EQ(count("poses_bad_values"), 6);
  EXPECT_EQ(count("poses_wrong_kind"), 2);
  EXPECT_EQ(count("poses_stale"), 7);
  EXPECT_EQ(count("poses_too_far_ahead"), 4) << "a sequence 2^62 ahead is refused, not taken";
  EXPECT_GE(count("poses_foreign"), 10) << "the stranger's poses, and what of its flood got through";
  EXPECT_GT(count("poses_flood_ticks"), 0);
  EXPECT_EQ(count("rejected_non_finite"), 0) << "the NaN never reached the device's state";
  // Through it all the device felt the plane's force, and at the end still does.
  ASSERT_FALSE(forces.empty());
  for (const auto& r : forces) ASSERT_TRUE(std::isfinite(norm(r.force.force_n)));
  EXPECT_NEAR(forces.back().force.force_n[2], kStiffness * 1.0, 1e-9);
}

// A stranger floods the simulation's port with junk while the device sends
// its poses, and goes on after the device stops. Junk is read and dropped a
// batch a poll and never counts as a frame's input: the haptic group keeps
// the device's 1 kHz (before, every datagram started a frame, 1,238 Hz at
// 5,000 junk packets a second), the device's poses are taken, and the
// watchdog trips when they stop however much junk still comes.
TEST(BridgeDeviceTest, JunkNeitherPacesTheFramesNorHidesADeviceThatStopped) {
  const PeerLink link = PeerLink::udp();
  constexpr double kDuration = 0.8;
  auto simulation = loadRealtime(pressScene(link.attributes()), kDuration);
  ASSERT_TRUE(simulation);
  FakeDevice device(
      link, [](double) { return poseAt(3.0, 1.5); }, [](double t) { return t < 0.4; });
  std::atomic<bool> done{false};
  std::atomic<uint64_t> junkSent{0};
  std::thread stranger([&] {
    trephine_bridge_address local{}, target{};
    trephine_bridge_address_parse("127.0.0.1", 0, &local);
    trephine_bridge_address_parse("127.0.0.1", link.simulationPort, &target);
    trephine_bridge_udp* socket = trephine_bridge_udp_open(&local, nullptr);
    ASSERT_NE(socket, nullptr);
    const unsigned char junk[200] = {'T', 'R', 'P', 'B'};
    while (!done) {
      // About 10,000 a second: ten packets every millisecond.
      for (int i = 0; i < 10; ++i) trephine_bridge_udp_send(socket, &target, junk, sizeof junk);
      junkSent += 10;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    trephine_bridge_udp_close(socket);
  });
  device.start();
  simulation->run();
  done = true;
  stranger.join();
  device.stop();
  const auto count = [&](const char* name) { return componentCounterAt(*simulation, "/tool/device", name); };
  EXPECT_GT(junkSent.load(), 3000u);
  EXPECT_GT(count("poses_foreign") + count("poses_malformed"), 2000) << "the junk was read and dropped";
  EXPECT_EQ(count("watchdog_trips"), 1) << "the device stopped at 0.4 s: junk does not keep the watchdog fed";
  const RateGroup& haptic = simulation->scheduler().groups().front();
  if (!kTimingChecked) return;
  EXPECT_LE(static_cast<double>(haptic.calls), 1000 * kDuration * 1.05 + 5) << "junk paced frames";
  EXPECT_GT(count("poses_received"), 300) << "the device's poses got through the junk";
}

// A device program started again mid-run numbers its poses from 1 in a new
// session (before, it got 0 N until it passed its old count): it is heard
// once the old session has been quiet for the watchdog's time, over shared
// memory and over UDP, and over UDP also from a new port with no fixed peer
// (before, never heard again).
TEST_P(BridgeTransportTest, ADeviceProgramStartedAgainIsHeardWithinTheWatchdogsTime) {
  const PeerLink link = GetParam().udp ? PeerLink::udp() : PeerLink::sharedMemory("restart");
  auto simulation = loadRealtime(pressScene(link.attributes()), 0.9);
  ASSERT_TRUE(simulation);
  // The first program: restarted in place at 0.25 s, gone at 0.5 s.
  FakeDevice first(
      link, [](double) { return poseAt(3.0, 1.5); }, [](double t) { return t < 0.5; });
  // Over UDP, a second program from a port of its own, from 0.55 s, pressing 0.5 mm.
  std::optional<FakeDevice> second;
  if (GetParam().udp)
    second.emplace(
        link, [](double) { return poseAt(3.0, 2.0); }, [](double t) { return t >= 0.55; });
  first.start();
  if (second) second->start();
  std::thread restarter([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    first.restart();
  });
  simulation->run();
  restarter.join();
  const auto forcesFirst = first.stop();
  const auto forcesSecond = second ? second->stop() : decltype(forcesFirst){};
  // After the restart (plus the watchdog's 20 ms of quiet and 20 ms of ramp): the spring's 2 N again.
  size_t full = 0;
  for (const auto& r : forcesFirst) {
    const double t = static_cast<double>(r.atNs - first.startNs()) * 1e-9;
    if (t > 0.25 + kTimeout + kRamp + 0.02 && t < 0.5 && std::abs(r.force.force_n[2] - kStiffness) < 1e-9) ++full;
  }
  EXPECT_GT(full, kTimingChecked ? 100u : 10u) << "the restarted program feels the plane";
  const auto count = [&](const char* name) { return componentCounterAt(*simulation, "/tool/device", name); };
  EXPECT_GE(count("device_restarts"), 1);
  if (second) {
    ASSERT_FALSE(forcesSecond.empty()) << "the program on a new port is answered";
    EXPECT_NEAR(forcesSecond.back().force.force_n[2], kStiffness * 0.5, 1e-9);
    EXPECT_EQ(count("device_restarts"), 2);
  }
}

// Another process truncates the shared memory object mid-run (before, the
// simulation died of SIGBUS, exit 135, with no summary and its folder
// marked running): the run hears no more poses, says why, ramps the force
// to zero and ends as planned.
TEST(BridgeDeviceTest, ATruncatedSharedMemoryEndsTheDeviceNotTheRun) {
  const PeerLink link = PeerLink::sharedMemory("truncated");
  auto simulation = loadRealtime(pressScene(link.attributes()), 0.5);
  ASSERT_TRUE(simulation);
  FakeDevice device(link, [](double) { return poseAt(3.0, 1.5); });
  std::thread vandal([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    const int fd = shm_open(link.channel.c_str(), O_RDWR, 0);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(ftruncate(fd, 0), 0);
    close(fd);
  });
  device.start();
  simulation->run();
  vandal.join();
  device.stop();
  shm_unlink(link.channel.c_str());
  EXPECT_TRUE(simulation->complete());
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "transport_lost"), 1);
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "watchdog_trips"), 1) << "the force ramped to zero";
  bool lost = false;
  const EventLog& events = simulation->events();
  for (size_t i = 0; i < events.size(); ++i) lost |= std::string(events[i].kind) == "bridge_lost";
  EXPECT_TRUE(lost);
}

TEST(BridgeDeviceTest, TheForceSentIsLimitedToMaxForceWithItsDirectionKept) {
  const PeerLink link = PeerLink::sharedMemory("limit");
  auto simulation = loadRealtime(pressScene(link.attributes() + " maxForce=\"1.25\""), 0.4);
  ASSERT_TRUE(simulation);
  // Pressing 1 mm on a slope of the plane's normal: the spring's 2 N straight up.
  FakeDevice device(link, [](double) { return poseAt(0.0, 1.5); });
  device.start();
  simulation->run();
  const auto forces = device.stop();
  size_t checked = 0;
  for (const auto& r : forces) {
    if (r.atNs < device.startNs() + 100'000'000) continue;
    EXPECT_NEAR(norm(r.force.force_n), 1.25, 1e-12);
    EXPECT_NEAR(r.force.force_n[2], 1.25, 1e-12);
    EXPECT_TRUE(r.force.flags & TREPHINE_BRIDGE_FORCE_CLAMPED);
    ++checked;
  }
  EXPECT_GT(checked, 150u);
  EXPECT_GT(componentCounterAt(*simulation, "/tool/device", "forces_limited"), 150);
}

TEST(BridgeDeviceTest, BadFieldsAreLoadErrorsThatSayWhatWasExpected) {
  for (const auto& [attributes, expected] : std::vector<std::pair<std::string, std::string>>{
           {"channel=\"no-slash\"", "not a shared memory name"},
           {"channel=\"/a/b\"", "not a shared memory name"},
           {"transport=\"udp\" address=\"localhost:27200\"", "not a dotted IPv4 address"},
           {"transport=\"udp\" address=\"127.0.0.1:0\"", "port from 1 to 65535"},
           {"transport=\"udp\" peer=\"127.0.0.1\"", "port from 1 to 65535"},
           {"transport=\"serial\"", "one of"},
           {"timeout=\"0\"", "timeout"}}) {
    expectLoadError(pressScene(attributes), expected, attributes);
  }
}

TEST(BridgeDeviceTest, InVirtualTimeTheLoadWarnsThatTheDeviceIsNotWaitedFor) {
  Diagnostics diagnostics;
  auto simulation = loadScene(pressScene(PeerLink::sharedMemory("virtual").attributes()), diagnostics);
  ASSERT_TRUE(simulation) << messages(diagnostics);
  EXPECT_NE(messages(diagnostics).find("--realtime"), std::string::npos) << messages(diagnostics);
  simulation->run();
  EXPECT_EQ(componentCounterAt(*simulation, "/tool/device", "samples"), 0) << "no device, no samples";
  EXPECT_GT(componentCounterAt(*simulation, "/tool/device", "frames_before_device"), 0);
}

}  // namespace
}  // namespace trephine::test
