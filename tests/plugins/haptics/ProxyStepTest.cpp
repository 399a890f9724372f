// The proxy's step as a function (ProxyStep.h), driven without a scene graph
// against an exact half-space written here: the rendered depth against its
// closed form, the slide along the surface, a replay from a copy of the
// memory, an invalid device frame and the release after a shape failure.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "plugins/haptics/ProxyStep.h"

namespace trephine::haptics {
namespace {

constexpr double kRadius = 2.0;  // mm, the spherical tool
constexpr double kSkin = 0.05;   // mm, the half-space's contactDepth

// Solid where z < 0. Exact: the deepest shell point gives the depth, and the
// line sweep stops the tool's leading point (its centre less kRadius) on z = 0
// when it moves deeper.
class HalfSpace final : public ShellContactTarget {
 public:
  Box3 bounds() const override { return Box3(Vec3(-100, -100, -100), Vec3(100, 100, 0)); }
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override {
    if (direction.z() >= 0 || origin.z() < 0) return std::nullopt;
    const double distance = -origin.z() / direction.z();
    if (distance > maxDistance) return std::nullopt;
    return SurfaceHit{origin + distance * direction, Vec3::UnitZ(), distance};
  }
  ContactMemory reserveShell(std::span<const ShellPoint>) override { return {}; }
  SweepResult sweep(const SweepQuery& query) const override {
    ++sweeps;
    SweepResult result;
    const double start = query.from.z() - query.leadingRadius, end = query.to.z() - query.leadingRadius;
    // Moving out, along the surface or above it: nothing stops the tool.
    if (end >= 0 || end >= start) return result;
    result.blocked = true;
    result.startsInside = start <= 0;
    result.freeFraction = result.startsInside ? 0.0 : start / (start - end);
    result.contactPoint =
        query.from + result.freeFraction * (query.to - query.from) - query.leadingRadius * Vec3::UnitZ();
    return result;
  }
  ShellContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool, ContactMemory&) override {
    ShellContact contact;
    for (const ShellPoint& p : shell) {
      const double z = (X_WT.position + X_WT.orientation * p.position).z();
      if (z < 0) {
        ++contact.points;
        contact.penetration = std::max(contact.penetration, -z);
      }
    }
    if (contact.points > 0) {
      contact.primitives = 1;
      contact.normal = Vec3::UnitZ();
    }
    return contact;
  }
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override {
    for (const ShellPoint& p : shell)
      if ((X_WT.position + X_WT.orientation * p.position).z() < -kSkin) return true;
    return false;
  }
  double contactDepth() const override { return kSkin; }

  mutable int sweeps = 0;
};

// A sphere of kRadius sampled on a Fibonacci spiral, with both poles.
std::vector<ShellPoint> sphereShell(int count) {
  std::vector<ShellPoint> shell;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 1 - 2 * (i + 0.5) / count, r = std::sqrt(1 - z * z);
    const Vec3 unit(r * std::cos(golden * i), r * std::sin(golden * i), z);
    shell.push_back({kRadius * unit, -unit});
  }
  shell.push_back({Vec3(0, 0, -kRadius), Vec3::UnitZ()});
  shell.push_back({Vec3(0, 0, kRadius), -Vec3::UnitZ()});
  return shell;
}

struct Stepper {
  HalfSpace target;
  std::vector<ShellPoint> shell = sphereShell(400);
  ProxySettings settings;
  ProxyMemory memory;
  ContactMemory contactMemory;
  uint64_t shapeFailures = 0;

  ProxyFrame step(const Vec3& device, bool valid = true) {
    ProxyInput input;
    input.deviceValid = valid;
    input.toolPose.position = device;
    input.frame.shapeFailures = shapeFailures;
    input.shell = shell;
    input.contactMemory = &contactMemory;
    input.leadingRadius = kRadius;
    return stepProxy(settings, memory, input, target);
  }
};

TEST(ProxyStepTest, PressedStraightDownTheRenderedDepthIsTheDevicesDepthBelowTheSurface) {
  Stepper stepper;
  for (const double depth : {0.3, 1.0, 2.5}) {
    stepper.memory = ProxyMemory{};
    // From 1 mm above the surface to `depth` below, 0.01 mm a frame, then held.
    const Vec3 above(0, 0, kRadius + 1);
    ProxyFrame frame;
    for (double z = above.z(); z > kRadius - depth; z -= 0.01) frame = stepper.step(Vec3(0, 0, z));
    const Vec3 device(0, 0, kRadius - depth);
    for (int i = 0; i < 50; ++i) frame = stepper.step(device);
    EXPECT_TRUE(frame.state.contact) << depth;
    // The proxy sits at most kSkin into the surface (where the sweep stopped
    // it), and the spring's anchor, the proxy lifted by that overlap, is on
    // the surface: the depth rendered is the device's, exactly.
    EXPECT_NEAR(frame.state.penetration, depth, 1e-12) << depth;
    EXPECT_NEAR(frame.state.normal.z(), 1.0, 1e-12) << depth;
    EXPECT_GT(frame.state.overlap, 0.0) << depth;
    EXPECT_LE(frame.state.overlap, kSkin) << depth;
    EXPECT_NEAR(frame.state.proxy.z() + frame.state.overlap, kRadius, 1e-12) << depth;
    EXPECT_FALSE(frame.state.proxyInside);
  }
}

TEST(ProxyStepTest, SlidingBeneathTheSurfaceTheProxyTrailsTheDeviceByAtMostTwoFramesOfItsMotion) {
  Stepper stepper;
  const double depth = 1.0, speed = 0.02;  // mm, mm per frame (20 mm/s at 1 kHz)
  for (double z = kRadius + 1; z > kRadius - depth; z -= 0.01) stepper.step(Vec3(0, 0, z));
  double lag = 0;
  for (int i = 0; i < 1000; ++i) {
    const Vec3 device(speed * i, 0, kRadius - depth);
    const ProxyFrame frame = stepper.step(device);
    ASSERT_TRUE(frame.state.contact) << i;
    // Halving the slide each frame lags a steady slide by one frame's motion
    // (the fixed point of x' = x + v, p' = p + (x' - p) / 2 is p = x - v).
    lag = device.x() - frame.state.proxy.x();
    ASSERT_GE(lag, -1e-12) << i;
    ASSERT_LE(lag, 2 * speed + 1e-12) << i;
    ASSERT_NEAR(frame.state.proxy.z() + frame.state.overlap, kRadius, 1e-12) << i;
    // The spring runs from the device to the anchor on the surface, the lag behind it (a drag).
    ASSERT_NEAR(frame.state.penetration, std::hypot(depth, lag), 1e-12) << i;
  }
  EXPECT_NEAR(lag, speed, 1e-9) << "the steady lag is one frame's motion";
}

// A copy of the memory is all the proxy keeps: stepping from it again
// replays the frames after it to the bit.
TEST(ProxyStepTest, ACopyOfTheMemoryReplaysTheFramesAfterItExactly) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  std::vector<Vec3> path;
  Vec3 device(0, 0, kRadius + 1);
  for (int i = 0; i < 3000; ++i) {
    // A random walk with a downward drift that bottoms out 1.5 mm below the
    // surface: free space, first contact, pressing and sliding.
    device += Vec3(jitter(random), jitter(random), jitter(random) - 0.01);
    device.z() = std::max(device.z(), kRadius - 1.5);
    path.push_back(device);
  }
  Stepper stepper;
  stepper.shell = sphereShell(100);  // the replay needs contact, not a fine shell (a sanitizer build runs it too)
  const size_t snapshotAt = 1200;
  ProxyMemory snapshot;
  std::vector<ProxyState> first;
  for (size_t i = 0; i < path.size(); ++i) {
    if (i == snapshotAt) snapshot = stepper.memory;
    first.push_back(stepper.step(path[i]).state);
  }
  int contacts = 0;
  for (const ProxyState& s : first) contacts += s.contact;
  ASSERT_GT(contacts, 1000) << "the path must touch the surface for the replay to mean something";
  stepper.memory = snapshot;
  for (size_t i = snapshotAt; i < path.size(); ++i) {
    const ProxyState s = stepper.step(path[i]).state;
    ASSERT_EQ(s.proxy, first[i].proxy) << i;
    ASSERT_EQ(s.normal, first[i].normal) << i;
    ASSERT_EQ(s.penetration, first[i].penetration) << i;
    ASSERT_EQ(s.contact, first[i].contact) << i;
  }
}

TEST(ProxyStepTest, AnInvalidDeviceFrameKeepsTheProxyAndRendersNothing) {
  Stepper stepper;
  for (double z = kRadius + 1; z > kRadius - 1; z -= 0.01) stepper.step(Vec3(0, 0, z));
  const Vec3 proxy = stepper.memory.state.proxy;
  const ProxyFrame frame = stepper.step(Vec3(50, 50, -50), false);
  EXPECT_FALSE(frame.state.deviceValid);
  EXPECT_FALSE(frame.state.contact);
  EXPECT_EQ(frame.state.proxy, proxy);
  EXPECT_EQ(frame.contact.points, 0);
}

TEST(ProxyStepTest, AShapeFailureLetsTheProxyGoOnceUntilTheToolIsClear) {
  Stepper stepper;
  for (double z = kRadius + 1; z > kRadius - 1; z -= 0.01) stepper.step(Vec3(0, 0, z));
  ASSERT_TRUE(stepper.memory.state.contact);
  ++stepper.shapeFailures;
  const Vec3 inside(0, 0, kRadius - 1);
  ProxyFrame frame = stepper.step(inside);
  EXPECT_TRUE(frame.letGo);
  EXPECT_TRUE(frame.state.released);
  EXPECT_FALSE(frame.state.contact);
  EXPECT_EQ(frame.state.proxy, inside);
  ++stepper.shapeFailures;  // another failure while let go: no second event
  frame = stepper.step(inside);
  EXPECT_FALSE(frame.letGo);
  EXPECT_TRUE(frame.state.released);
  // Clear of the target (no shell point deeper than the skin), it works again.
  frame = stepper.step(Vec3(0, 0, kRadius + 0.5));
  EXPECT_TRUE(frame.state.released);
  frame = stepper.step(Vec3(0, 0, kRadius + 0.5));
  EXPECT_FALSE(frame.state.released);
  EXPECT_EQ(stepper.memory.counters.releases, 1u);
}

}  // namespace
}  // namespace trephine::haptics
