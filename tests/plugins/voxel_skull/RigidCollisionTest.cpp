// Hard cases of rigid voxel collision: each test drives a pointshell burr
// through a scene and asserts no NaN, no pop-through, and forces bounded by
// what the device's own motion explains: k times its depth below the surface
// it came from (plus the proxy's contact skin) and b times its speed. The
// scenes' maxForce is far above every such force, so the clamp never acts and
// the bound is the rendering's own.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "framework/core/Node.h"
#include "framework/formats/volume/VolumeWriter.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kRadius = 2.5;     // mm, burr radius
constexpr double kStiffness = 2.0;  // N/mm
constexpr double kDamping = 0.002;  // N*s/mm
constexpr double kDt = 0.001;       // s, one haptic frame

struct SceneParts {
  std::string skull = R"(file="phantom:halfspace?voxel=0.5" isovalue="500")";
  std::string device;  // attributes of the ScriptedDevice
  std::string proxy = R"(sweep="line")";
  std::string tool = R"(<PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>)";
  std::string force = R"(stiffness="2.0" damping="0.002" maxForce="1000")";
};

std::string sceneXml(const SceneParts& p) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" )" +
         p.skull + R"(/>
  <ScriptedDevice name="device" record="false" )" +
         p.device + R"(/>
  )" + p.tool +
         R"(
  <GodObjectProxy name="proxy" tool="@burr" target="@skull" )" +
         p.proxy + R"(/>
  <ForceFeedback name="force" proxy="@proxy" )" +
         p.force + R"(/>
</Node>)";
}

std::unique_ptr<Simulation> run(const SceneParts& parts, const std::string& file = "inline.xml") {
  Diagnostics d;
  auto simulation = test::loadScene(sceneXml(parts), d, {}, file);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (simulation) simulation->run();
  return simulation;
}

// Waypoints "t x y z ..." along z at x = y = 0.
std::string verticalWaypoints(std::initializer_list<std::pair<double, double>> tz) {
  std::string s = R"(path="waypoints" maxSpeed="1e6" waypoints=")";
  for (const auto& [t, z] : tz) s += std::to_string(t) + " 0 0 " + std::to_string(z) + " ";
  return s + "\"";
}

constexpr double kCatchUp = 0.02;  // mm a frame (ProxyStep.cpp)

// The device's depth (mm) below the surface of the scene's target that it
// approaches from, as a function of its position: how far the burr would be
// in the bone were it where the device is.
using DeviceDepth = std::function<double(const Vec3&)>;

// Below the plane z = top (a half-space or a wall's top face) for a tool that reaches `reach` below its centre.
DeviceDepth belowPlane(double top, double reach = kRadius) {
  return [top, reach](const Vec3& device) { return std::max(0.0, top + reach - device.z()); };
}

// No NaN, and in every frame a force that the device's motion explains:
//   |F| <= k (depth + skin + catch-up) + b |v|,
// depth from `depth`, skin the proxy's contact depth (0.1 voxel), catch-up
// the 0.02 mm a frame by which the spring may trail a proxy that lands back
// (its change a frame is held to the device's move plus that), v the
// device's backward-difference velocity; and never pulling towards the target
// (F . n >= 0). Returns the largest |F| for the tests' own closed forms.
double expectStable(const HapticFrameLog& log, const char* what, const DeviceDepth& depth, double voxel = 0.5) {
  const HapticStats s = log.stats();
  EXPECT_EQ(s.nanFrames, 0u) << what;
  const double skin = 0.1 * voxel;
  double largest = 0;
  for (size_t i = 0; i < log.size(); ++i) {
    const HapticFrame& f = log[i];
    EXPECT_TRUE(f.force.allFinite()) << what << " frame " << i;
    if (!f.force.allFinite()) return largest;
    const double speed = i == 0 ? 0.0 : (f.device - log[i - 1].device).norm() / kDt;
    // The spring runs from the device to the proxy: beside the depth, the
    // proxy's lag across the surface (every target here is a plane of normal
    // +z; the proxy catches up at a bounded pace) pulls too.
    const Vec3 offset = f.proxy - f.device;
    const double across = std::hypot(offset.x(), offset.y());
    const double explained = kStiffness * (depth(f.device) + skin + kCatchUp + across) + kDamping * speed;
    EXPECT_LE(f.force.norm(), explained + 1e-9)
        << what << ", t = " << f.t << ": device at " << f.device.transpose() << ", " << depth(f.device)
        << " mm deep, moving at " << speed << " mm/s";
    EXPECT_GE(f.force.dot(f.normal), -1e-12) << what << ", t = " << f.t << ": the force pulls the tool in";
    if (testing::Test::HasFailure()) return largest;  // one frame's message is enough
    largest = std::max(largest, f.force.norm());
  }
  return largest;
}

TEST(RigidCollisionTest, OneVoxelWallCrossedAtTenVoxelsPerFrameDoesNotPopThrough) {
  for (const char* surface : {"smooth", "voxels"}) {
    SceneParts p;
    p.skull = std::string(R"(file="phantom:wall?voxel=0.5&thickness=0.5&size=40.5" isovalue="500" surface=")") +
              surface + "\"";
    // 5 mm per 1 ms frame = 10 voxels per frame, from 10 mm above the wall to 10 mm below.
    p.device = verticalWaypoints({{0, 10}, {0.004, -10}, {0.1, -10}});
    auto simulation = run(p);
    ASSERT_TRUE(simulation);
    const HapticFrameLog& log = simulation->hapticLog();
    // The wall spans z in [-0.25, 0.25]: depths count from its top face.
    expectStable(log, surface, belowPlane(0.25));
    EXPECT_EQ(log.stats().proxyInsideFrames, 0u) << surface;
    for (size_t i = 0; i < log.size(); ++i) {
      // The burr centre stays above the wall.
      ASSERT_GT(log[i].proxy.z(), 0.25) << surface << ", frame " << i;
      if (log[i].device.z() < 0) {
        ASSERT_GT(log[i].force.z(), 0.0) << surface << ": force points back up, frame " << i;
      }
    }
    // At rest 12.75 mm below where the burr touches the top face: the spring of
    // that depth, straight up, within k times the proxy's contact skin (0.05 mm;
    // the voxel boxes render 12.70 mm, the smooth surface 12.75 mm).
    const HapticFrame& last = log[log.size() - 1];
    EXPECT_NEAR(last.force.z(), kStiffness * 12.75, kStiffness * 0.05 + 1e-9) << surface << ": 12.75 mm past the top";
    EXPECT_NEAR(std::hypot(last.force.x(), last.force.y()), 0.0, 1e-9) << surface;
  }
}

TEST(RigidCollisionTest, ToolStartingInsideBoneIsBoundedAndLeaves) {
  SceneParts p;
  // Starts 5 mm below the surface of a half-space (fully inside), then rises out.
  p.device = verticalWaypoints({{0, -5}, {0.05, -5}, {1.0, 10}, {1.1, 10}});
  auto simulation = run(p);
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  // Lifted out along the normal by the depth measured there, the proxy can
  // land up to 0.1 mm above the surface in the first frames: 0.2 N at k = 2.
  expectStable(log, "inside", belowPlane(0.0, kRadius + 0.1));
  const HapticFrame& last = log[log.size() - 1];
  EXPECT_EQ(last.contacts, 0);
  EXPECT_NEAR((last.proxy - last.device).norm(), 0.0, 1e-9) << "proxy rejoins the device once out";
}

TEST(RigidCollisionTest, VolumeBorderAndToolPartlyOutsideTheGrid) {
  // The half-space grid spans [-20, 20] mm; the burr presses at x = 19 (half outside).
  SceneParts p;
  p.device = R"(path="waypoints" waypoints="0 19 0 5  0.5 19 0 1.5  1.0 19 0 1.5  1.5 25 0 1.5  2.0 25 0 1.5")";
  auto simulation = run(p);
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  expectStable(log, "border", belowPlane(0.0));
  EXPECT_GT(log.stats().contactFrames, 0u);
  const HapticFrame& pressed = log[900];
  EXPECT_GT(pressed.contacts, 0);
  EXPECT_GT(pressed.normal.z(), 0.95) << "normal still up at the border";
  EXPECT_NEAR(pressed.penetration, 1.0, 0.1);
  EXPECT_EQ(log[log.size() - 1].contacts, 0) << "outside the grid: nothing to touch";
}

TEST(RigidCollisionTest, ShellPointsExactlyOnVoxelFacesAndCorners) {
  // Voxel 1 mm: voxel faces at integer + 0.5 offsets of the grid corner. The half-space
  // surface is at z = 0, a voxel face; with the burr centre at z = 2.5 its bottom
  // point is exactly on that face, and at x = y = 0.5 on voxel corners.
  // Nudged by +-1e-9 mm the results must not jump: every point is counted in one voxel.
  for (const Vec3& at : {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0)}) {
    for (double depth : {0.0, 0.5, 1.0}) {
      for (double nudge : {0.0, 1e-9, -1e-9}) {
        SceneParts p;
        p.skull = R"(file="phantom:halfspace?voxel=1.0" isovalue="500")";
        const Vec3 c = at + Vec3(nudge, nudge, kRadius - depth + nudge);
        const std::string xyz = std::to_string(c.x()) + " " + std::to_string(c.y()) + " " + std::to_string(c.z());
        p.device = R"(path="waypoints" waypoints="0 )" + xyz + " 0.01 " + xyz + R"(")";
        auto simulation = run(p);
        ASSERT_TRUE(simulation);
        const HapticFrameLog& log = simulation->hapticLog();
        expectStable(log, "faces", belowPlane(0.0), 1.0);
        const HapticFrame& f = log[log.size() - 1];
        const std::string where = "at " + xyz;
        if (depth == 0.0) {
          EXPECT_LE(f.penetration, 1e-6) << "touching exactly: no penetration " << where;
        } else {
          EXPECT_NEAR(f.penetration, depth, 1e-3) << where;
          EXPECT_GT(f.normal.z(), 0.9999) << where;
          EXPECT_NEAR(f.force.z(), kStiffness * depth, kStiffness * 1e-3) << where;
        }
      }
    }
  }
}

TEST(RigidCollisionTest, AnisotropicSpacingOfTheOriginalSkull) {
  // A half-space written with the thesis's original spacing 0.984 x 1.584 x 0.997 mm.
  test::TempDir dir;
  DensityVolume volume({60, 40, 40}, Vec3(0.984, 1.584, 0.997),
                              Vec3(-29.5 * 0.984, -19.5 * 1.584, -19.5 * 0.997));
  for (int k = 0; k < 40; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 60; ++i) volume.setDensity(i, j, k, volume.voxelCenter(i, j, k).z() < 0 ? 1000.0 : 0.0);
  formats::writeMetaImage(volume, dir / "anisotropic.mha", false);
  const double surface = -19.5 * 0.997 + 20 * 0.997 - 0.5 * 0.997;  // top face of the last solid layer
  SceneParts p;
  p.skull = R"(file="anisotropic.mha" isovalue="500")";
  const double z = surface + kRadius - 0.8;
  p.device = R"(path="waypoints" waypoints="0 0 0 )" + std::to_string(z + 5) + " 0.5 0 0 " + std::to_string(z) +
             " 1.0 0 0 " + std::to_string(z) + R"(")";
  dir.write("scene.xml", sceneXml(p));
  Diagnostics d;
  auto simulation = Simulation::fromFile(dir / "scene.xml", {}, d);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  const HapticFrameLog& log = simulation->hapticLog();
  expectStable(log, "anisotropic", belowPlane(surface), 0.984);
  const HapticFrame& f = log[log.size() - 1];
  EXPECT_NEAR(f.penetration, 0.8, 0.05);
  EXPECT_NEAR(f.force.norm(), kStiffness * f.penetration, 1e-9) << "at rest: the spring alone";
  EXPECT_GT(f.normal.z(), 0.99);
  EXPECT_EQ(log.stats().proxyInsideFrames, 0u);
}

TEST(RigidCollisionTest, CavityNarrowerThanTheToolLineAndCylinderSweeps) {
  // A 3 mm channel along z through a block whose top is at z = 19 mm; the 5 mm
  // burr comes straight down the channel axis to z = 10.
  double lowest[2];
  int k = 0;
  for (const char* sweep : {"line", "cylinder"}) {
    SceneParts p;
    p.skull = R"(file="phantom:channel?voxel=0.5&width=3" isovalue="500")";
    p.device = verticalWaypoints({{0, 30}, {0.5, 10}, {1.0, 10}});
    p.proxy = std::string(R"(sweep=")") + sweep + R"(")";
    auto simulation = run(p);
    ASSERT_TRUE(simulation);
    const HapticFrameLog& log = simulation->hapticLog();
    // Depths from where the burr rests on the rim, 2 mm above the top (below).
    expectStable(log, sweep, belowPlane(19.0, 2.0));
    lowest[k] = 1e9;
    for (size_t i = 0; i < log.size(); ++i) lowest[k] = std::min(lowest[k], log[i].proxy.z());
    if (std::string(sweep) == "cylinder") {
      EXPECT_GT(log[log.size() - 1].force.z(), 0.5) << "the rim holds the burr";
    }
    ++k;
  }
  // Resting on the rim, the burr centre is sqrt(2.5^2 - 1.5^2) = 2 mm above the top (z = 21).
  // The line sweep follows the leading point down the channel, which it
  // alone would let the burr sink into the block along (its limit); a place
  // that shows the burr inside is refused for the last free one on the way,
  // so it rests at the rim too. The cylinder's front rings stop the burr
  // where they meet the rim, within 1 mm of resting.
  EXPECT_GT(lowest[1], 20.0) << "cylinder keeps the burr at the channel's rim";
  EXPECT_GT(lowest[0], 20.0) << "line: the proxy is held at the last free place, at the rim";
  RecordProperty("line_lowest_mm", std::to_string(lowest[0]));
  RecordProperty("cylinder_lowest_mm", std::to_string(lowest[1]));
}

TEST(RigidCollisionTest, DrillingThroughAPlateUntilTheToolPasses) {
  for (const char* surface : {"smooth", "voxels"}) {
    SceneParts p;
    p.skull = std::string(R"(file="phantom:wall?voxel=0.5&thickness=2&size=40.5" isovalue="500" drill="true" )") +
              R"(removal="thesis" drillRate="50" surface=")" + surface + "\"";
    // Feed from 5 mm above to 8 mm below the plate at 2 mm/s.
    p.device = verticalWaypoints({{0, 5}, {0.2, 3.6}, {6.0, -8}, {6.5, -8}});
    auto simulation = run(p);
    ASSERT_TRUE(simulation);
    const HapticFrameLog& log = simulation->hapticLog();
    // Drilling only removes bone: depths count from the plate's first top face (z = 1).
    expectStable(log, surface, belowPlane(1.0));
    EXPECT_GT(test::componentCounter(*simulation, "VoxelSkull", "voxels_removed"), 0.0) << surface;
    const HapticFrame& last = log[log.size() - 1];
    EXPECT_LT(last.proxy.z(), -1.0 - kRadius + 0.5) << surface << ": the burr went through the plate";
    EXPECT_EQ(last.contacts, 0) << surface;
    EXPECT_EQ(log.stats().proxyInsideFrames, 0u) << surface;
  }
}

TEST(RigidCollisionTest, SlowDrillingWithTheCylinderSweepNeverEntersTheBone) {
  // The feed (2 mm/s) outruns the cut (1 per frame on bone of 1500 over an isovalue of 400):
  // the burr presses a pit narrower than itself. Neither sweep lets it into the pit, and the
  // cylinder still cuts what stops it.
  size_t inside[2];
  double lowest[2];
  int k = 0;
  for (const char* sweep : {"line", "cylinder"}) {
    SceneParts p;
    p.skull = R"(file="phantom:wall?voxel=0.5&thickness=6&size=40.5&density=1500" isovalue="400" )"
              R"(drill="true" removal="thesis" drillRate="1")";
    p.proxy = std::string(R"(sweep=")") + sweep + "\"";
    p.device = verticalWaypoints({{0, 8}, {0.5, 5.5}, {2.5, 1.5}, {5.0, 1.5}});
    auto simulation = run(p);
    ASSERT_TRUE(simulation);
    const HapticFrameLog& log = simulation->hapticLog();
    // The wall's top face before drilling, z = 3, where the voxel centred on it
    // holds 750: the isovalue 400 puts the smooth surface (350/750) half a voxel
    // above it, at z = 3.233.
    expectStable(log, sweep, belowPlane(3.0 + 0.5 * 350.0 / 750.0));
    inside[k] = log.stats().proxyInsideFrames;
    lowest[k] = log[log.size() - 1].proxy.z();
    ++k;
  }
  // The line sweep alone once let the burr slip into its pit; the lift out
  // along the normal, taken before the rectifying sweep, now keeps it out too.
  EXPECT_EQ(inside[0], 0u) << "line: never inside the bone";
  EXPECT_EQ(inside[1], 0u) << "cylinder: never inside the bone";
  EXPECT_LT(lowest[1], 3.0 + kRadius - 0.5) << "cylinder: the burr cut into the wall (top face at 3)";
}

TEST(RigidCollisionTest, IsovalueAboveTheDensestVoxelMeansNoContact) {
  SceneParts p;
  p.skull = R"(file="phantom:halfspace?voxel=0.5" isovalue="5000")";
  p.device = verticalWaypoints({{0, 5}, {0.5, -3}, {0.6, -3}});
  auto simulation = run(p);
  ASSERT_TRUE(simulation);
  EXPECT_EQ(simulation->hapticLog().stats().contactFrames, 0u);
  EXPECT_EQ(simulation->hapticLog().stats().forceMax, 0.0);
}

TEST(RigidCollisionTest, NaNDevicePoseIsRejectedAndTheForceHeld) {
  SceneParts p;
  p.device = verticalWaypoints({{0, 5}, {0.3, 1.5}, {0.6, 1.5}});
  p.device += R"( nanTimes="0.4 0.401 0.45")";
  auto simulation = run(p);
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  expectStable(log, "nan", belowPlane(0.0));
  // Frames at the rejected samples hold the force of the frame before.
  for (double t : {0.4, 0.401, 0.45}) {
    const size_t i = static_cast<size_t>(std::lround(t * 1000));
    EXPECT_NEAR((log[i].force - log[i - 1].force).norm(), 0.0, 1e-12) << "t = " << t;
    EXPECT_NEAR(log[i].force.z(), kStiffness * 1.0, kStiffness * 1e-3) << "still pressing 1 mm deep at t = " << t;
  }
}

TEST(RigidCollisionTest, CapsuleShaftTouchingAWallPushesBack) {
  // A burr on a 20 mm shaft along +x lies level over a 2 mm wall (faces at z = +-1);
  // the shaft, not the burr, rests on the wall.
  SceneParts p;
  p.skull = R"(file="phantom:wall?voxel=0.5&thickness=2&size=40.5" isovalue="500")";
  p.tool =
      R"(<CapsuleTool name="burr" radius="2.5" shaftRadius="1.0" shaftLength="20" axis="1 0 0" device="@device"/>)";
  // Burr centre beyond the wall's edge (x = -25, the grid spans 40.5 mm), shaft across it,
  // its underside at 1.65 - 1.0 = 0.65: 0.35 mm into the wall.
  p.device = R"(path="waypoints" waypoints="0 -25 0 4  0.5 -25 0 1.65  1.0 -25 0 1.65")";
  for (const char* surface : {"smooth", "voxels"}) {
    p.skull = std::string(R"(file="phantom:wall?voxel=0.5&thickness=2&size=40.5" isovalue="500" )") +
              R"(penetration="deepest-point" surface=")" + surface + R"(")";
    auto simulation = run(p);
    ASSERT_TRUE(simulation);
    const HapticFrameLog& log = simulation->hapticLog();
    // The shaft (radius 1 around the device's axis) approaches the wall's top face (z = 1).
    expectStable(log, "capsule", belowPlane(1.0, 1.0));
    const HapticFrame& f = log[log.size() - 1];
    EXPECT_GT(f.contacts, 0) << surface << ": the shaft touches";
    EXPECT_GT(f.force.z(), 0.0) << surface;
    // The voxel centres at z = +-1 hold exactly the isovalue (half-filled): as voxels
    // the wall ends at +-0.75 (0.10 mm deep), as a smooth surface at +-1 (0.35 mm).
    EXPECT_NEAR(f.penetration, std::string(surface) == "voxels" ? 0.10 : 0.35, 0.02) << surface;
  }
}

}  // namespace
}  // namespace trephine
