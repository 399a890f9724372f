// Scripted paths reach what they promise on any target geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "framework/devices/DeviceStream.h"
#include "framework/devices/HapticDevice.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kRadius = 2.5;  // mm, sphere tool radius in every scene here

std::string scene(const std::string& deviceAttributes, const std::string& planeAttributes = "") {
  return R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <AnalyticPlane name="plane" )" +
         planeAttributes + R"(/>
  <ScriptedDevice name="device" target="@plane" tipOffset="2.5" )" +
         deviceAttributes + R"(/>
  <SphereTool name="burr" radius="2.5" device="@device"/>
  <SpringForce name="force" tool="@burr" target="@plane" rate="1000"/>
</Node>)";
}

std::unique_ptr<Simulation> run(const std::string& xml, uint64_t seed = 0) {
  Diagnostics d;
  SimulationOptions options;
  options.seed = seed;
  auto simulation = test::loadScene(xml, d, options);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (simulation) simulation->run();
  return simulation;
}

// Number of separate stretches of frames in contact.
int contactEpisodes(const HapticFrameLog& log) {
  int episodes = 0;
  for (size_t i = 0; i < log.size(); ++i)
    if (log[i].contacts > 0 && (i == 0 || log[i - 1].contacts == 0)) ++episodes;
  return episodes;
}

TEST(ScriptedDeviceTest, ApproachPressSlidePressesTheToolToItsDepthAndLeaves) {
  auto simulation = run(scene(R"(path="approach-press-slide" depth="1.5" slideDistance="10" speed="20")"));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  EXPECT_NEAR(log.stats().penetrationMax, 1.5, 1e-9);
  EXPECT_EQ(contactEpisodes(log), 1);
  EXPECT_EQ(log[0].contacts, 0) << "starts off the surface";
  EXPECT_EQ(log[log.size() - 1].contacts, 0) << "ends off the surface";
  // Slid 10 mm along the surface while pressed.
  double minX = 1e9, maxX = -1e9;
  for (size_t i = 0; i < log.size(); ++i)
    if (log[i].contacts) minX = std::min(minX, log[i].device.x()), maxX = std::max(maxX, log[i].device.x());
  EXPECT_NEAR(maxX - minX, 10.0, 1e-6);
}

TEST(ScriptedDeviceTest, AimsAtATiltedSurfaceAlongTheGivenDirection) {
  auto simulation =
      run(scene(R"(path="approach-press-slide" depth="1" direction="0 -1 -1")", R"(point="5 5 5" normal="0 1 1")"));
  ASSERT_TRUE(simulation);
  EXPECT_NEAR(simulation->hapticLog().stats().penetrationMax, 1.0, 1e-9);
}

TEST(ScriptedDeviceTest, DrillInFeedsAtTheFeedSpeed) {
  auto simulation = run(scene(R"(path="drill-in" depth="2" feedSpeed="4")"));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  size_t firstContact = 0, deepest = 0;
  for (size_t i = 0; i < log.size(); ++i) {
    if (!firstContact && log[i].contacts) firstContact = i;
    if (log[i].penetration > log[deepest].penetration) deepest = i;
  }
  EXPECT_NEAR(log[deepest].penetration, 2.0, 1e-9);
  EXPECT_NEAR(log[deepest].t - log[firstContact].t, 2.0 / 4.0, 0.002) << "depth / feed speed";
}

TEST(ScriptedDeviceTest, CircleKeepsItsRadiusAroundTheAimPoint) {
  auto simulation = run(scene(R"(path="circle" radius="4" depth="0.5" turns="1" period="1" center="10 0 0")"));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  int pressedFrames = 0;
  for (size_t i = 0; i < log.size(); ++i) {
    if (std::abs(log[i].penetration - 0.5) > 1e-9) continue;
    ++pressedFrames;
    EXPECT_NEAR(std::hypot(log[i].device.x() - 10.0, log[i].device.y()), 4.0, 1e-9);
  }
  EXPECT_GE(pressedFrames, 1000) << "one turn of one second at full depth";
}

TEST(ScriptedDeviceTest, RandomWalkIsSeededAndStaysWithinItsDepths) {
  const std::string xml = scene(R"(path="random-walk" radius="5" depth="2" walkDuration="3")");
  auto a = run(xml, 1), b = run(xml, 1), c = run(xml, 2);
  ASSERT_TRUE(a && b && c);
  EXPECT_EQ(a->hapticLog()[1500].device, b->hapticLog()[1500].device);
  EXPECT_NE(a->hapticLog()[1500].device, c->hapticLog()[1500].device);
  EXPECT_LE(a->hapticLog().stats().penetrationMax, 2.0 + 1e-9);
  EXPECT_GT(a->hapticLog().stats().contactFrames, 0u);
  EXPECT_LT(a->hapticLog().stats().contactFrames, a->hapticLog().size()) << "slight and strong contacts, and none";
}

TEST(ScriptedDeviceTest, PokesTouchTheSurfaceCountTimes) {
  auto simulation = run(scene(R"(path="pokes" count="7" radius="3" depth="1" lift="2")"));
  ASSERT_TRUE(simulation);
  EXPECT_EQ(contactEpisodes(simulation->hapticLog()), 7);
  EXPECT_NEAR(simulation->hapticLog().stats().penetrationMax, 1.0, 1e-9);
}

TEST(ScriptedDeviceTest, WaypointsAreFollowedExactlyAtTheirTimes) {
  // Waypoints (t; x y z): (0; 0 0 10), (0.5; 5 0 10), (1.0; 5 5 0), straight
  // lines at constant speed in between and the last point held after it. The
  // run is 2 ms longer than the path, so the frame at t = 1.0 is sampled too.
  const std::string xml = R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device" path="waypoints" waypoints="0 0 0 10  0.5 5 0 10  1.0 5 5 0" rate="1000"/>
</Node>)";
  {
    Diagnostics d;
    auto planned = test::loadScene(xml, d);
    ASSERT_TRUE(planned) << test::messages(d);
    EXPECT_DOUBLE_EQ(planned->plan().duration, 1.0) << "the path asks for its last waypoint's time";
  }
  Diagnostics d;
  SimulationOptions options;
  options.duration = 1.002;
  auto simulation = test::loadScene(xml, d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  test::TempDir dir;
  simulation->writeOutputs(dir / "run");
  const DeviceStreamReadResult stream = readDeviceStream(dir / "run/device.device.csv");
  ASSERT_TRUE(stream.error.empty()) << stream.error;
  ASSERT_EQ(stream.samples.size(), 1002u) << "one sample per 1 ms frame";

  // Closed form of the piecewise linear path.
  const auto expected = [](double t) {
    if (t <= 0.5) return Vec3(10.0 * t, 0, 10);                             // 0 -> 5 in x over 0.5 s
    if (t <= 1.0) return Vec3(5, 10.0 * (t - 0.5), 10 - 20.0 * (t - 0.5));  // 0 -> 5 in y, 10 -> 0 in z
    return Vec3(5, 5, 0);
  };
  const auto sampleAt = [&](double t) -> const DeviceSample& {
    const size_t i = static_cast<size_t>(std::lround(t * 1000));
    EXPECT_NEAR(stream.samples.at(i).t, t, 1e-12);
    return stream.samples.at(i);
  };
  // Every waypoint at its time, and the midpoints of both legs.
  const std::vector<std::pair<double, Vec3>> checkpoints = {{0.0, Vec3(0, 0, 10)}, {0.25, Vec3(2.5, 0, 10)},
                                                            {0.5, Vec3(5, 0, 10)}, {0.75, Vec3(5, 2.5, 5)},
                                                            {1.0, Vec3(5, 5, 0)},  {1.001, Vec3(5, 5, 0)}};
  for (const auto& [t, at] : checkpoints) {
    const DeviceSample& sample = sampleAt(t);
    EXPECT_NEAR((sample.position - at).norm(), 0.0, 1e-12) << "t = " << t << ": " << sample.position.transpose();
    EXPECT_NEAR((expected(t) - at).norm(), 0.0, 1e-12) << "the closed form itself at t = " << t;
  }
  // And every frame in between lies on the lines at the scheduled speed.
  for (const DeviceSample& sample : stream.samples)
    ASSERT_NEAR((sample.position - expected(sample.t)).norm(), 0.0, 1e-12) << "t = " << sample.t;
  // The device's state after the run: the last waypoint, at rest.
  const auto* device = dynamic_cast<const HapticDevice*>(simulation->scene().findComponent("device"));
  ASSERT_TRUE(device);
  EXPECT_NEAR((device->state().pose.position - Vec3(5, 5, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(device->state().velocity.norm(), 0.0, 1e-9);
}

// Velocity (mm/s) changes by less than `bound` between consecutive frames: the
// script has no corners, so force changes come from contact, not from the motion.
class SmoothPathTest : public testing::TestWithParam<std::string> {};

TEST_P(SmoothPathTest, VelocityHasNoJumps) {
  auto simulation = run(scene(GetParam()), 3);
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  double largestChange = 0;  // mm/s per frame
  for (size_t i = 2; i < log.size(); ++i) {
    const Vec3 v1 = (log[i - 1].device - log[i - 2].device) * 1000.0, v2 = (log[i].device - log[i - 1].device) * 1000.0;
    largestChange = std::max(largestChange, (v2 - v1).norm());
  }
  EXPECT_LT(largestChange, 2.0) << GetParam() << ": a velocity jump of " << largestChange << " mm/s in one frame";
}

INSTANTIATE_TEST_SUITE_P(Paths, SmoothPathTest,
                         testing::Values(R"(path="approach-press-slide" depth="1")", R"(path="drill-in" depth="1")",
                                         R"(path="circle" depth="1" radius="4" period="1" turns="1")",
                                         R"(path="random-walk" depth="1" radius="4" walkDuration="2")",
                                         R"(path="pokes" depth="1" radius="4" count="3")"),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param.substr(6, info.param.find('"', 6) - 6);
                           std::erase(name, '-');
                           return name;
                         });

TEST(ScriptedDeviceTest, AFieldThePathDoesNotUseIsAnError) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(scene(R"(path="circle" slideDistance="5")"), d));
  EXPECT_NE(test::messages(d).find("inline.xml:5:94: error: invalid slideDistance of ScriptedDevice 'device': has no "
                                   "effect with path=\"circle\" (it is used by approach-press-slide)"),
            std::string::npos)
      << test::messages(d);
}

TEST(ScriptedDeviceTest, ReportsAnApproachThatMissesTheTarget) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(scene(R"(path="approach-press-slide" direction="1 0 0" center="0 0 10")"), d));
  EXPECT_NE(test::messages(d).find("inline.xml:5:3: error: ScriptedDevice 'device': the approach ray through 0 0 10 "
                                   "along 1 0 0 misses /plane"),
            std::string::npos)
      << test::messages(d);
}

TEST(ScriptedDeviceTest, ReportsMalformedWaypoints) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ScriptedDevice name="device" path="waypoints" waypoints="0 0 0 10 1 2"/>
</Node>)",
                               d));
  EXPECT_NE(test::messages(d).find("inline.xml:3:61: error: invalid waypoints of ScriptedDevice 'device': path=waypoints needs groups of four"),
            std::string::npos)
      << test::messages(d);
}

TEST(ScriptedDeviceTest, AimsTheToolsSphereNotItsAxisAtASlotNarrowerThanTheTool) {
  // A 20 x 20 x 10 mm bone block (0.5 mm voxels) with a 3 mm slot, 5 mm deep,
  // across its top (isosurface walls at x = 8.25 and 11.25 mm). Aimed down the
  // middle of the slot, a ray reaches its floor, but the 2.5 mm sphere rests
  // on the rims: its centre 2 mm above the top (sqrt(2.5^2 - 1.5^2)). The
  // axis ray alone would press it to 6.75 mm, into the slot.
  test::TempDir dir;
  std::string voxels;
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) {
        const bool slot = x >= 17 && x < 23 && z >= 10;
        const int16_t value = slot ? 0 : 1000;
        voxels.append(reinterpret_cast<const char*>(&value), 2);
      }
  dir.write("slot.raw", voxels);
  const auto header = dir.write("slot.mhd",
                                "ObjectType = Image\nNDims = 3\nDimSize = 40 40 20\nElementSpacing = 0.5 0.5 0.5\n"
                                "ElementType = MET_SHORT\nElementByteOrderMSB = False\nElementDataFile = slot.raw\n");
  Diagnostics d;
  auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="block" file=")" + header.string() + R"(" isovalue="500" drill="false"/>
  <ScriptedDevice name="device" target="@block" tipOffset="2.5" center="9.75 10 0" direction="0 0 -1"
                  path="approach-press-slide" depth="0.5" slideDistance="0" rate="1000"/>
  <PointshellTool name="burr" radius="2.5" pointCount="466" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@block" sweep="cylinder" rate="1000"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2" rate="1000"/>
</Node>)",
                                    d);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  const HapticFrameLog& log = simulation->hapticLog();
  double lowest = 1e9;
  for (size_t i = 0; i < log.size(); ++i) lowest = std::min(lowest, log[i].device.z());
  // The block's top is at about 9.75 mm (the isosurface half a voxel above the last bone centre).
  // 0.2 mm lower here: the smooth isosurface rounds the rims (and the aim may sit 0.05 mm low).
  EXPECT_NEAR(lowest, 9.75 + 2.0 - 0.5, 0.3) << "pressed 0.5 mm onto the rims, not into the slot";
}

}  // namespace
}  // namespace trephine
