// A device that jumps a kilometre in one frame (its jump filter off:
// maxSpeed="1e300") through the target it presses on. The proxy must stay on
// the surface it was pressed against (the target lies between it and the
// device), and any force must come from a proxy at the target: never a proxy
// carried metres along its constraint plane, nor contact rendered far from
// everything. Every target type: the voxel skull, the tetrahedral brain, and
// the analytic plane (a spring without a proxy).
#include <gtest/gtest.h>

#include <random>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kJump = 1e6;  // mm

std::string waypoint(double t, const Vec3& p) {
  char text[160];
  std::snprintf(text, sizeof text, "%.4f %.17g %.17g %.17g  ", t, p.x(), p.y(), p.z());
  return text;
}

// Down onto `surface` to 1 mm deep (the probe's centre 1.5 mm above it), held,
// then a jump of kJump along `through` in one frame, held 0.5 s there.
std::string path(const Vec3& surface, const Vec3& through) {
  const Vec3 pressed = surface + Vec3(0, 0, 1.5);
  return waypoint(0, surface + Vec3(0, 0, 10)) + waypoint(0.3, pressed) + waypoint(0.5, pressed) +
         waypoint(0.501, pressed + kJump * through) + waypoint(1.0, pressed + kJump * through);
}

std::string proxyScene(const std::string& target, const std::string& waypoints) {
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  )" + target +
         R"(
  <ScriptedDevice name="device" record="false" path="waypoints" maxSpeed="1e300" waypoints=")" +
         waypoints + R"("/>
  <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
  <GodObjectProxy name="proxy" tool="@probe" target="@target"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2" damping="0.002" maxForce="3.3"/>
</Node>)";
}

// A direction into the target, within 30 degrees of straight down.
Vec3 downwards(std::mt19937& random) {
  std::uniform_real_distribution<double> tilt(0.0, 0.5), turn(0.0, 6.283185307179586);
  const double a = tilt(random), b = turn(random);
  return Vec3(std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), -std::cos(a));
}

// After the jump: the proxy within a few millimetres of where it pressed
// (the god-object may slide it along the surface by a few frames' catch-up),
// and every frame that renders a force has its proxy there too.
void expectProxyStaysOnTheSurface(const std::string& target, const Vec3& surface, const Vec3& through,
                                  const std::string& what) {
  auto simulation = test::runScene(proxyScene(target, path(surface, through)));
  ASSERT_TRUE(simulation) << what;
  const HapticFrameLog& log = simulation->hapticLog();
  ASSERT_EQ(log.size(), 1000u);
  double farthest = 0;
  size_t forceFarAway = 0;
  for (size_t i = 500; i < log.size(); ++i) {
    const double away = (log[i].proxy - surface).norm();
    farthest = std::max(farthest, away);
    if (log[i].force.norm() > 0 && away > 20.0) ++forceFarAway;
  }
  // 0.5 s of catch-up at 0.02 mm a frame is 10 mm; the tool's radius more.
  EXPECT_LT(farthest, 15.0) << what;
  EXPECT_EQ(forceFarAway, 0u) << what;
  // Still on the surface at the end, pressed against it.
  EXPECT_GT(log[log.size() - 1].force.norm(), 1.0) << what;
}

TEST(ProxyJumpTest, OnTheVoxelSkullTheProxyStaysWhereItPressed) {
  const std::string target =
      R"(<VoxelSkull name="target" file="phantom:skull?voxel=1.0" isovalue="400" drill="false"/>)";
  std::mt19937 random(5);
  std::uniform_real_distribution<double> across(-25.0, 25.0);
  for (int k = 0; k < 3; ++k) {
    // The skull phantom's outer surface is the ellipsoid of semi-axes
    // (104.75, 99.25, 69.25) mm.
    const double x = across(random), y = across(random);
    const double z = 69.25 * std::sqrt(1 - (x / 104.75) * (x / 104.75) - (y / 99.25) * (y / 99.25));
    const Vec3 through = downwards(random);
    expectProxyStaysOnTheSurface(target, Vec3(x, y, z), through,
                                 "skull at (" + std::to_string(x) + ", " + std::to_string(y) + ")");
  }
}

TEST(ProxyJumpTest, OnTheTetrahedralBrainTheProxyStaysWhereItPressed) {
  const std::string target = R"(<TetraBrain name="target" file="phantom:cube?cells=6&amp;size=40"/>)";
  // Within 10 mm of the middle of the 40 mm top: 0.5 s of catch-up towards
  // the device's far projection (10 mm) keeps the probe on the top.
  std::mt19937 random(6);
  std::uniform_real_distribution<double> across(-7.0, 7.0);
  for (int k = 0; k < 3; ++k) {
    const Vec3 surface(across(random), across(random), 20.0);
    expectProxyStaysOnTheSurface(target, surface, downwards(random),
                                 "cube at (" + std::to_string(surface.x()) + ", " + std::to_string(surface.y()) + ")");
  }
}

TEST(ProxyJumpTest, SlidOffAnEdgeTheProxyJoinsTheDeviceAndNothingIsRendered) {
  // Pressed 4 mm from the edge y = 20 of the cube's top, the device jumps a
  // kilometre down and out past that edge: the proxy slides along the top
  // towards the device's projection, off the edge, and then nothing stands
  // between it and the device.
  const std::string target = R"(<TetraBrain name="target" file="phantom:cube?cells=6&amp;size=40"/>)";
  const Vec3 surface(0, 16, 20);
  auto simulation = test::runScene(proxyScene(target, path(surface, Vec3(0, 0.5, -1).normalized())));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  size_t forceFarAway = 0;
  for (size_t i = 500; i < log.size(); ++i)
    if (log[i].force.norm() > 0 && (log[i].proxy - surface).norm() > 20.0) ++forceFarAway;
  EXPECT_EQ(forceFarAway, 0u);
  const HapticFrame& last = log[log.size() - 1];
  EXPECT_EQ(last.force.norm(), 0.0);
  EXPECT_EQ(last.contacts, 0);
  EXPECT_LT((last.proxy - last.device).norm(), 1e-6);
  EXPECT_GE(test::componentCounter(*simulation, "GodObjectProxy", "released_holds"), 1.0);
}

TEST(ProxyJumpTest, OnTheAnalyticPlaneTheSpringsProxyStaysOnThePlane) {
  // SpringForce has no proxy to carry away: its proxy is the sphere moved back
  // onto the plane, wherever the device is.
  std::mt19937 random(8);
  const Vec3 through = downwards(random);
  const std::string xml = R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <AnalyticPlane name="plane" point="0 0 0" normal="0 0 1"/>
  <ScriptedDevice name="device" record="false" path="waypoints" maxSpeed="1e300" waypoints=")" +
                          path(Vec3(3, 4, 0), through) + R"("/>
  <SphereTool name="probe" radius="2.5" device="@device"/>
  <SpringForce name="force" tool="@probe" target="@plane" stiffness="2" maxForce="3.3"/>
</Node>)";
  auto simulation = test::runScene(xml);
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  for (size_t i = 501; i < log.size(); ++i) {  // from the jump on
    ASSERT_NEAR(log[i].proxy.z(), 2.5, 1e-6) << "t = " << log[i].t;
    ASSERT_NEAR(log[i].force.norm(), 3.3, 1e-9) << "t = " << log[i].t;
  }
}

}  // namespace
}  // namespace trephine
