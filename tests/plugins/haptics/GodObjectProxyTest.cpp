// GodObjectProxy against closed forms on voxel phantoms: the god-object
// projection on a flat surface and without it (godObject="false"), the
// rectifying sweep (rectify="false"), and the crease of an inside corner.
//
// The 2.5 mm burr's proxy is placed contactDepth = 0.1 voxel = 0.05 mm into
// the bone when a sweep stops it (its contact skin), so "on a plane" means:
// the burr's surface between touching it and the skin below it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "framework/runtime/RunOutputs.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kRadius = 2.5;     // mm, burr radius
constexpr double kSkin = 0.05;      // mm, VoxelSkull::contactDepth at 0.5 mm voxels
constexpr double kStiffness = 0.5;  // N/mm; every force here stays far below maxForce

std::string sceneXml(const std::string& skull, const std::string& waypoints, const std::string& proxyAttributes) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" file=")" +
         skull + R"(" isovalue="500"/>
  <ScriptedDevice name="device" record="false" path="waypoints" waypoints=")" +
         waypoints + R"("/>
  <PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull" )" +
         proxyAttributes + R"(/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="0.5" damping="0" maxForce="10"/>
</Node>)";
}

std::unique_ptr<Simulation> run(const std::string& xml) { return test::runScene(xml); }

double proxyCounter(const Simulation& simulation, const std::string& name) {
  return test::componentCounter(simulation, "GodObjectProxy", name);
}

// ---------------------------------------------------------------------------
// A flat half-space (top face z = 0), pressed diagonally: the device moves in a
// straight line from (0, 0, 5) to (3, 0, 1.5) in 0.2 s (1 mm deep at the end)
// and holds there for 0.2 s.
const std::string kHalfSpace = "phantom:halfspace?voxel=0.5";
const Vec3 kFrom(0, 0, 5), kTo(3, 0, 1.5);
const std::string kDiagonalPress = "0 0 0 5  0.1 0 0 5  0.3 3 0 1.5  0.5 3 0 1.5";

TEST(GodObjectProxyTest, OnAFlatSurfaceTheProxySlidesOverTheDeviceAndTheForceIsTheSpring) {
  auto simulation = run(sceneXml(kHalfSpace, kDiagonalPress, ""));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  ASSERT_EQ(log.size(), 500u);
  EXPECT_EQ(log.stats().proxyInsideFrames, 0u);
  // The device moves at most this far along x in a frame (mm): 3 mm in 0.2 s
  // on a straight line, 15 mm/s.
  const double frameMove = 3.0 / 0.2 * 0.001;
  for (size_t i = 0; i < log.size(); ++i) {
    // Never in the bone deeper than its skin, and the force k times the device's depth.
    ASSERT_GE(log[i].proxy.z(), kRadius - kSkin - 1e-9) << "t = " << log[i].t;
    const double depth = std::max(0.0, kRadius - log[i].device.z());
    ASSERT_NEAR(log[i].force.z(), kStiffness * depth, 1e-3) << "t = " << log[i].t;
    // Sliding, the spring trails the device by the proxy's lag: a drag of k
    // times that lag, the lag at most one frame's move (the half-steps converge).
    if (depth > 0) {
      ASSERT_NEAR(log[i].force.x(), kStiffness * (log[i].proxy.x() - log[i].device.x()), 1e-9);
    }
    ASSERT_LE(std::abs(log[i].force.x()), kStiffness * frameMove + 1e-9) << "t = " << log[i].t;
  }
  // At rest: the proxy on the surface straight above the device (the tangential
  // half-steps have converged), the force k * 1 mm straight up.
  const HapticFrame& last = log[log.size() - 1];
  EXPECT_NEAR((last.proxy - Vec3(3, 0, kRadius - kSkin)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((last.force - Vec3(0, 0, kStiffness * 1.0)).norm(), 0.0, 1e-3);
  EXPECT_EQ(proxyCounter(*simulation, "crease_frames"), 0.0) << "one plane";
}

TEST(GodObjectProxyTest, WithoutTheGodObjectTheProxyStaysWhereTheSweepLeftIt) {
  // godObject="false": no projection on the constraint plane, so the proxy is
  // wherever the sweep before moving put it: on the device's own path, never
  // beside it; with the line sweep, stopped where the burr's leading point (r
  // along the motion) meets the surface, plus at most the contact skin along
  // the path; and there it stays while the device holds.
  auto simulation = run(sceneXml(kHalfSpace, kDiagonalPress, R"(godObject="false")"));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  ASSERT_EQ(log.size(), 500u);
  const Vec3 u = (kTo - kFrom).normalized();
  size_t firstContact = 0;
  for (size_t i = 0; i < log.size(); ++i) {
    const Vec3 along = log[i].proxy - kFrom;
    ASSERT_NEAR((along - along.dot(u) * u).norm(), 0.0, 1e-9) << "on the device's path, t = " << log[i].t;
    ASSERT_LE(along.dot(u), (log[i].device - kFrom).dot(u) + 1e-9) << "never ahead of the device, t = " << log[i].t;
    if (!firstContact && log[i].contacts > 0) firstContact = i;
  }
  ASSERT_GT(firstContact, 0u);
  const HapticFrame& last = log[log.size() - 1];
  const double leadingPointZ = last.proxy.z() + kRadius * u.z();
  EXPECT_LE(leadingPointZ, 1e-3) << "the leading point reached the surface";
  EXPECT_GE(leadingPointZ, -kSkin) << "and went at most the contact skin further";
  // Once the device holds (t >= 0.3 s) the proxy does not move at all.
  for (size_t i = 301; i < log.size(); ++i) ASSERT_EQ(log[i].proxy, log[300].proxy) << "t = " << log[i].t;
  // It did not slide over the device as the god-object does (x = 3 there).
  EXPECT_LT(last.proxy.x(), 3.0 - 0.2);
  // The force: k times the depth of the device below the proxy along the
  // normal, plus the proxy's own contact skin (its raw depth exceeds the skin).
  ASSERT_GT(last.rawPenetration, kSkin);
  EXPECT_NEAR(last.normal.z(), 1.0, 1e-9);
  EXPECT_NEAR(last.force.z(), kStiffness * (last.proxy.z() - last.device.z() + kSkin), 1e-9);
  EXPECT_EQ(proxyCounter(*simulation, "crease_frames"), 0.0);
}

// ---------------------------------------------------------------------------
// A square channel 12 mm wide along z (walls at x = +-6 and y = +-6, solid
// beyond): its inside corner at x = y = 6 is a crease of two half-spaces with
// normals -x and -y. Where the burr touches both walls its centre is on the
// crease line x = y = 6 - r = 3.5.
const std::string kChannel = "phantom:channel?voxel=0.5&width=12";
constexpr double kWall = 6.0;
constexpr double kCrease = kWall - kRadius;  // 3.5 mm

// How deep the burr at `proxy` is in the wall x = 6 and in the wall y = 6 (mm, < 0: clear of it).
double overlapX(const Vec3& proxy) { return proxy.x() + kRadius - kWall; }
double overlapY(const Vec3& proxy) { return proxy.y() + kRadius - kWall; }

// Presses the wall x = 6 to 1 mm deep (x = 4.5) at y = 0, then slides along
// it in +y to `endY`, arriving at `arrival` s (0.6: 15 mm/s; 0.305: a jump of
// 4.5 mm in 5 frames).
std::string slideIntoTheCorner(double endY, double arrival = 0.6) {
  return "0 0 0 0  0.1 4.5 0 0  0.3 4.5 0 0  " + std::to_string(arrival) + " 4.5 " + std::to_string(endY) +
         " 0  0.8 4.5 " + std::to_string(endY) + " 0";
}

TEST(GodObjectProxyTest, TheRectifyingSweepKeepsTheGodObjectOutOfTheOtherWall) {
  // Sliding along the wall x = 6 into the wall y = 6 with the device 1 mm
  // beyond both: the god-object goal (the device projected on the wall x = 6)
  // lies inside the wall y = 6. The rectifying sweep stops the proxy on its
  // way there; without it the proxy jumps in. The spheres sweep tests the
  // whole shell, so the sweep before moving never lets it in.
  const auto deepest = [](const Simulation& simulation) {
    const HapticFrameLog& log = simulation.hapticLog();
    double x = -1e9, y = -1e9;
    for (size_t i = 0; i < log.size(); ++i) {
      x = std::max(x, overlapX(log[i].proxy));
      y = std::max(y, overlapY(log[i].proxy));
    }
    return std::pair{x, y};
  };
  auto rectified = run(sceneXml(kChannel, slideIntoTheCorner(4.5), R"(sweep="spheres")"));
  auto unrectified = run(sceneXml(kChannel, slideIntoTheCorner(4.5), R"(sweep="spheres" rectify="false")"));
  ASSERT_TRUE(rectified && unrectified);
  const auto [rx, ry] = deepest(*rectified);
  EXPECT_LE(rx, kSkin + 1e-6) << "rectified: never deeper than the skin in the wall x = 6";
  EXPECT_LE(ry, kSkin + 1e-6) << "rectified: nor in the wall y = 6";
  // Unrectified, the god-object step crosses into the wall y = 6 (by less
  // than before the slide was held to the device's move plus 0.02 mm a frame).
  const auto [ux, uy] = deepest(*unrectified);
  EXPECT_GT(uy, kSkin + 0.01) << "unrectified: into the wall y = 6";
  (void)ux;
}

TEST(GodObjectProxyTest, CreaseFramesAreCountedWhereTheSlideMeetsTheSecondWallOnly) {
  // The same jump along the wall x = 6 (line sweep), once stopping at y = 3
  // (the burr 0.5 mm clear of the wall y = 6: one plane all along) and once
  // into the corner, where the new constraint plane's projection crosses the
  // last one. A slow slide meets the second wall gradually: the averaged
  // normal turns by less than the crease branch's 2.6 degrees a frame, and
  // the god-object alone settles in the corner (CreaseTest).
  auto clear = run(sceneXml(kChannel, slideIntoTheCorner(3.0, 0.305), ""));
  auto corner = run(sceneXml(kChannel, slideIntoTheCorner(4.5, 0.305), ""));
  ASSERT_TRUE(clear && corner);
  EXPECT_EQ(proxyCounter(*clear, "crease_frames"), 0.0);
  const HapticFrame& end = clear->hapticLog()[clear->hapticLog().size() - 1];
  EXPECT_NEAR((end.force - Vec3(-kStiffness * 1.0, 0, 0)).norm(), 0.0, 1e-9) << "k * 1 mm out of the wall x = 6";
  EXPECT_GT(proxyCounter(*corner, "crease_frames"), 0.0);
  EXPECT_EQ(proxyCounter(*clear, "contact_frames"), proxyCounter(*corner, "contact_frames"))
      << "both in contact from the first touch of the wall x = 6 to the end";
}

// The crease: the device ends 1 mm beyond the wall x = 6 (x = 4.5) and
// `beyondY` beyond the wall y = 6, having slid along the first wall into the
// second. Closed form: the proxy sits on both walls, on the crease line
// C = (3.5, 3.5, z), and the force is k |D - C| along C - D, between the two
// normals. The proxy may sit anywhere within its contact skin of each wall,
// which moves the rendered depth by up to the skin (k * skin = 0.025 N) and
// turns the force by up to atan(sqrt(2) skin / |D - C|).
struct CreaseCase {
  std::string sweep;
  double beyondY;  // mm
  double arrival;  // s, when the device reaches the corner (0.6: a slide; 0.305: a jump)
};

void PrintTo(const CreaseCase& c, std::ostream* out) {
  *out << "sweep " << c.sweep << ", " << c.beyondY << " mm beyond y = 6, arriving at " << c.arrival << " s";
}

class CreaseTest : public testing::TestWithParam<CreaseCase> {};

TEST_P(CreaseTest, TheProxySitsOnBothWallsAndTheForceIsTheSpringToTheCreaseLine) {
  const CreaseCase& c = GetParam();
  const double endY = kCrease + c.beyondY;
  auto simulation = run(sceneXml(kChannel, slideIntoTheCorner(endY, c.arrival), "sweep=\"" + c.sweep + "\""));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  ASSERT_EQ(log.size(), 800u);
  const HapticFrame& last = log[log.size() - 1];
  const Vec3 D(4.5, endY, 0), C(kCrease, kCrease, 0);
  ASSERT_NEAR((last.device - D).norm(), 0.0, 1e-9);

  // The proxy on both walls.
  EXPECT_GE(overlapX(last.proxy), -0.02) << c.sweep << ": touches the wall x = 6; proxy " << last.proxy.transpose();
  EXPECT_LE(overlapX(last.proxy), kSkin + 0.02) << c.sweep << ": within its skin of the wall x = 6";
  EXPECT_GE(overlapY(last.proxy), -0.02) << c.sweep << ": touches the wall y = 6; proxy " << last.proxy.transpose();
  EXPECT_LE(overlapY(last.proxy), kSkin + 0.02) << c.sweep << ": within its skin of the wall y = 6";
  // The force between the two normals (-x and -y), along C - D, of magnitude k |D - C|.
  const Vec3 F = last.force;
  EXPECT_LT(F.x(), 0.0) << c.sweep << ": pushes out of the wall x = 6";
  EXPECT_LT(F.y(), 0.0) << c.sweep << ": pushes out of the wall y = 6; F " << F.transpose();
  EXPECT_NEAR(F.z(), 0.0, 1e-9);
  const double distance = (D - C).norm();
  EXPECT_NEAR(F.norm(), kStiffness * distance, kStiffness * kSkin + 0.005)
      << c.sweep << ": F " << F.transpose() << ", device " << distance << " mm from the crease line";
  const double angle = std::acos(std::clamp(F.normalized().dot((C - D).normalized()), -1.0, 1.0));
  EXPECT_LT(angle, std::atan(std::numbers::sqrt2 * kSkin / distance) + 0.005)
      << c.sweep << ": F " << F.transpose() << " is " << angle * 180 / std::numbers::pi << " degrees off C - D";
  // And it rests there: the device holds for the last 0.2 s.
  double largestStep = 0;
  for (size_t i = 701; i < log.size(); ++i)
    largestStep = std::max(largestStep, (log[i].force - log[i - 1].force).norm());
  EXPECT_LT(largestStep, 1e-3) << c.sweep << ": the force of a resting hand in a corner chatters";
}

std::string creaseName(const testing::TestParamInfo<CreaseCase>& info) {
  return info.param.sweep + (info.param.beyondY == 1.0 ? "_symmetric" : "_asymmetric") +
         (info.param.arrival < 0.5 ? "_jump" : "_slide");
}

// Not the line sweep's jump: with one averaged constraint plane across the
// corner, the god-object goal lies inside both walls, and the leading point's
// line runs into the corner between them, so the rectifying sweep does not
// stop it; the proxy rests 0.33 mm (0.17 mm) inside both walls and |F| is
// 0.50 N for 0.71 N (docs/results.md). The cylinder's and spheres' probes
// see the walls.
INSTANTIATE_TEST_SUITE_P(Sweeps, CreaseTest,
                         testing::Values(CreaseCase{"line", 1.0, 0.6}, CreaseCase{"line", 0.7, 0.6},
                                         CreaseCase{"cylinder", 1.0, 0.6}, CreaseCase{"cylinder", 0.7, 0.6},
                                         CreaseCase{"spheres", 1.0, 0.6}, CreaseCase{"spheres", 0.7, 0.6},
                                         CreaseCase{"cylinder", 1.0, 0.305}, CreaseCase{"cylinder", 0.7, 0.305},
                                         CreaseCase{"spheres", 1.0, 0.305}, CreaseCase{"spheres", 0.7, 0.305}),
                         creaseName);

// A tool whose first pose is inside the target (here 1.5 mm into the
// half-space) renders the whole depth at once: it is an event, counted, and
// the run's summary says it; a tool that starts clear of it says nothing.
TEST(GodObjectProxyTest, AToolThatStartsInsideTheTargetIsAnEventAndAWarningOfTheRun) {
  auto inside = run(sceneXml(kHalfSpace, "0 0 0 1  0.2 0 0 1", ""));
  ASSERT_TRUE(inside);
  EXPECT_EQ(proxyCounter(*inside, "starts_inside"), 1);
  size_t events = 0;
  for (size_t i = 0; i < inside->events().size(); ++i)
    if (std::string_view(inside->events()[i].kind) == "tool_starts_inside") {
      ++events;
      EXPECT_EQ(inside->events()[i].t, 0.0);
      EXPECT_NEAR(inside->events()[i].value, 1.5, 0.1) << "the depth: 2.5 mm burr, centre 1 mm above the surface";
    }
  EXPECT_EQ(events, 1u);
  std::ostringstream summary;
  printRunSummary(*inside, summary);
  EXPECT_NE(summary.str().find("warning   0.000 s, /proxy: tool_starts_inside: the tool's first pose is inside"),
            std::string::npos)
      << summary.str();
  auto clear = run(sceneXml(kHalfSpace, kDiagonalPress, ""));
  ASSERT_TRUE(clear);
  EXPECT_EQ(proxyCounter(*clear, "starts_inside"), 0);
  std::ostringstream quiet;
  printRunSummary(*clear, quiet);
  EXPECT_EQ(quiet.str().find("warning"), std::string::npos) << quiet.str();
}

}  // namespace
}  // namespace trephine
