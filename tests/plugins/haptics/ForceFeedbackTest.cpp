// ForceFeedback against closed forms: a 2.5 mm burr driven straight into a
// flat bone half-space (top face z = 0, normal +z) at known constant speeds,
// so that every frame's force is known: F = max(0, k p - b v_n) n with p the
// depth of the device below the surface (2.5 - z) and v_n the device's
// backward-difference velocity along n. The forces stay well below maxForce,
// so nothing here depends on the force clamp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "framework/core/Diagnostics.h"
#include "framework/runtime/RunOutputs.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

constexpr double kRadius = 2.5;  // mm, burr radius
constexpr double kDt = 0.001;    // s, one haptic frame at 1 kHz

std::string sceneXml(const std::string& waypoints, const std::string& forceAttributes) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" file="phantom:halfspace?voxel=0.5" isovalue="500"/>
  <ScriptedDevice name="device" record="false" path="waypoints" waypoints=")" +
         waypoints + R"("/>
  <PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull"/>
  <ForceFeedback name="force" proxy="@proxy" maxForce="10" )" +
         forceAttributes + R"(/>
</Node>)";
}

std::unique_ptr<Simulation> run(const std::string& xml) { return test::runScene(xml); }

// The device's height above the surface plane on a piecewise linear script of (t, z) knots.
struct VerticalScript {
  std::vector<std::pair<double, double>> knots;
  std::string waypoints() const {
    std::string s;
    for (const auto& [t, z] : knots) s += std::to_string(t) + " 0 0 " + std::to_string(z) + "  ";
    return s;
  }
  double z(double t) const {
    if (t <= knots.front().first) return knots.front().second;
    for (size_t i = 1; i < knots.size(); ++i)
      if (t <= knots[i].first) {
        const auto [t0, z0] = knots[i - 1];
        const auto [t1, z1] = knots[i];
        return z0 + (z1 - z0) * (t - t0) / (t1 - t0);
      }
    return knots.back().second;
  }
};

TEST(ForceFeedbackTest, DampingAddsToThePressAndSubtractsFromThePullAndNeverPulls) {
  // k = 0.5 N/mm, b = 0.02 N s/mm. Down from 1.5 mm above the surface to 1 mm
  // deep at 10 mm/s, hold 0.1 s, back up at 10 mm/s: b v = 0.2 N. Pressing:
  // F = k p + 0.2; holding: F = k p; pulling out: F = k p - 0.2 while the
  // depth exceeds 0.4 mm, and 0 (not a pull) above it although still in contact.
  const double k = 0.5, b = 0.02, speed = 10.0;
  const VerticalScript script{{{0, 4}, {0.1, 4}, {0.35, 1.5}, {0.45, 1.5}, {0.7, 4}, {0.8, 4}}};
  auto simulation = run(sceneXml(script.waypoints(), R"(stiffness="0.5" damping="0.02")"));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  ASSERT_EQ(log.size(), 800u);
  int pressing = 0, holding = 0, pullingPushes = 0, pullingZero = 0;
  for (size_t i = 1; i < log.size(); ++i) {
    const HapticFrame& f = log[i];
    const double z = script.z(f.t), zBefore = script.z(f.t - kDt);
    ASSERT_NEAR(f.device.z(), z, 1e-9) << "t = " << f.t;
    const double depth = kRadius - z;                // mm, the device below the surface
    const double normalSpeed = (z - zBefore) / kDt;  // mm/s, backward difference as the device measures it
    if (depth <= 1e-6) {
      EXPECT_EQ(f.force, Vec3::Zero()) << "free at t = " << f.t;
      continue;
    }
    ASSERT_GT(f.contacts, 0) << "t = " << f.t;
    const double expected = std::max(0.0, k * depth - b * normalSpeed);
    EXPECT_NEAR(f.force.z(), expected, 2e-3) << "t = " << f.t << ", depth " << depth << ", v " << normalSpeed;
    EXPECT_NEAR(f.force.x(), 0.0, 1e-9);
    EXPECT_NEAR(f.force.y(), 0.0, 1e-9);
    EXPECT_GE(f.force.z(), 0.0) << "never pulls the hand in, t = " << f.t;
    if (std::abs(normalSpeed + speed) < 1e-6) ++pressing;
    if (std::abs(normalSpeed) < 1e-9) ++holding;
    if (std::abs(normalSpeed - speed) < 1e-6) (k * depth > b * speed + 0.01 ? ++pullingPushes : ++pullingZero);
  }
  // The phases the closed form distinguishes were all met.
  EXPECT_GE(pressing, 90) << "0.1 s pressing in at 10 mm/s";
  EXPECT_GE(holding, 90);
  EXPECT_GE(pullingPushes, 50);
  EXPECT_GE(pullingZero, 30) << "pulled out faster than the spring relaxes: no force, not a pull";
  // At the same depth (0.8 mm: z = 1.7, 0.23 s into the press and 0.02 s into
  // the pull), pressing meets 2 b v = 0.4 N more than pulling out.
  const size_t inAt = static_cast<size_t>(std::lround((0.1 + 2.3 / speed) * 1000));
  const size_t outAt = static_cast<size_t>(std::lround((0.45 + 0.2 / speed) * 1000));
  EXPECT_NEAR(log[inAt].device.z(), log[outAt].device.z(), 1e-9);
  EXPECT_NEAR(log[inAt].force.z() - log[outAt].force.z(), 2 * b * speed, 2e-3);
  EXPECT_NEAR(log[inAt].force.z(), k * 0.8 + b * speed, 2e-3);
}

TEST(ForceFeedbackTest, WithoutDampingTheForceIsTheSpringAtAnySpeed) {
  // The same press with b = 0: the velocity term is what the test above measured.
  const VerticalScript script{{{0, 4}, {0.1, 4}, {0.35, 1.5}, {0.45, 1.5}, {0.7, 4}, {0.8, 4}}};
  auto simulation = run(sceneXml(script.waypoints(), R"(stiffness="0.5" damping="0")"));
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  for (size_t i = 0; i < log.size(); ++i) {
    const double depth = std::max(0.0, kRadius - script.z(log[i].t));
    EXPECT_NEAR(log[i].force.z(), 0.5 * depth, 1e-3) << "t = " << log[i].t;
  }
}

TEST(ForceFeedbackTest, MaxForceStepRampsAForceJumpAtTheStepAndCountsTheLimitedFrames) {
  // The device jumps from 0.5 mm above the surface to 1 mm deep in one frame
  // (t = 0.1 to 0.101), holds, and jumps back out at t = 0.3. Unlimited, the
  // force steps 0 -> k p = 0.5 N and back at once. With maxForceStep = 0.06 N
  // it rises by exactly 0.06 N per frame for 8 frames (0.48 N) and reaches
  // 0.5 N on the 9th (a step of 0.02 N, not limited); the same down again.
  const double k = 0.5, limit = 0.06, full = 0.5;
  const std::string path = "0 0 0 3  0.1 0 0 3  0.101 0 0 1.5  0.3 0 0 1.5  0.301 0 0 3  0.4 0 0 3";
  auto limited = run(sceneXml(path, R"(stiffness="0.5" damping="0" maxForceStep="0.06")"));
  auto unlimited = run(sceneXml(path, R"(stiffness="0.5" damping="0")"));
  ASSERT_TRUE(limited && unlimited);
  const HapticFrameLog& a = limited->hapticLog();
  const HapticFrameLog& u = unlimited->hapticLog();
  ASSERT_EQ(a.size(), 400u);
  ASSERT_EQ(u.size(), 400u);

  // The unlimited force: the spring's closed form, jumping by 0.5 N in one frame each way.
  EXPECT_NEAR(u[101].force.z(), k * 1.0, 1e-3);
  EXPECT_NEAR(u[100].force.norm(), 0.0, 1e-12);
  EXPECT_NEAR(u[301].force.norm(), 0.0, 1e-12);
  EXPECT_EQ(test::componentCounter(*unlimited, "ForceFeedback", "step_limited_frames"), 0.0);

  // The limited force: no frame changes by more than the limit...
  for (size_t i = 1; i < a.size(); ++i)
    ASSERT_LE((a[i].force - a[i - 1].force).norm(), limit + 1e-12) << "t = " << a[i].t;
  // ...it ramps by exactly the limit, reaching the unlimited value after ceil(0.5 / 0.06) = 9 frames...
  for (int j = 1; j <= 8; ++j) {
    EXPECT_NEAR(a[100 + j].force.z(), j * limit, 1e-9) << "frame " << j << " of the rise";
    EXPECT_NEAR(a[300 + j].force.z(), full - j * limit, 2e-3) << "frame " << j << " of the fall";
  }
  EXPECT_NEAR(a[109].force.z(), u[109].force.z(), 1e-12) << "the unlimited force reached on the 9th frame";
  EXPECT_NEAR(a[309].force.norm(), 0.0, 1e-12) << "and released on the 9th";
  for (size_t i = 109; i < 300; ++i) ASSERT_EQ(a[i].force, u[i].force) << "no lag left, t = " << a[i].t;
  // ...and exactly the 8 + 8 limited frames are counted.
  EXPECT_EQ(test::componentCounter(*limited, "ForceFeedback", "step_limited_frames"), 16.0);
}

TEST(ForceFeedbackTest, MaxForceStepLeavesASmoothPressAlone) {
  // Pressing at 10 mm/s with k = 0.5 changes the force by 0.005 N per frame:
  // a limit of 0.01 N never acts, and the force is the unlimited one.
  const VerticalScript script{{{0, 4}, {0.1, 4}, {0.35, 1.5}, {0.45, 1.5}, {0.7, 4}, {0.8, 4}}};
  auto simulation = run(sceneXml(script.waypoints(), R"(stiffness="0.5" damping="0" maxForceStep="0.01")"));
  ASSERT_TRUE(simulation);
  EXPECT_EQ(test::componentCounter(*simulation, "ForceFeedback", "step_limited_frames"), 0.0);
  const HapticFrameLog& log = simulation->hapticLog();
  for (size_t i = 0; i < log.size(); ++i)
    EXPECT_NEAR(log[i].force.z(), 0.5 * std::max(0.0, kRadius - script.z(log[i].t)), 1e-3) << "t = " << log[i].t;
}

// Every tool is measured: two burrs on one half-space, the first writing
// trace.csv and the summary's haptics, the second its own
// trace.second.force.csv; summary.json's tools holds both, each with the
// figures of its own frames (the second presses twice as deep: twice the
// force), and the printed summary has one haptics line per tool, named.
TEST(ForceFeedbackTest, EveryToolHasItsTraceItsFiguresAndItsLine) {
  const std::string xml = R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" file="phantom:halfspace?voxel=0.5" isovalue="500"/>
  <Node name="first">
    <ScriptedDevice name="device" record="false" path="waypoints" waypoints="0 -10 0 4  0.1 -10 0 2  0.3 -10 0 2"/>
    <PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>
    <GodObjectProxy name="proxy" tool="@burr" target="@/skull"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness="1" maxForce="10"/>
  </Node>
  <Node name="second">
    <ScriptedDevice name="device" record="false" path="waypoints" waypoints="0 10 0 4  0.1 10 0 1.5  0.3 10 0 1.5"/>
    <PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>
    <GodObjectProxy name="proxy" tool="@burr" target="@/skull"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness="1" maxForce="10" trace="false"/>
  </Node>
</Node>)";
  test::TempDir dir;
  Diagnostics d;
  SimulationOptions options;
  options.outputDirectory = dir.path();
  auto simulation = test::loadScene(xml, d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  const std::vector<std::string> written = simulation->writeOutputs(dir.path());
  EXPECT_NE(std::find(written.begin(), written.end(), "trace.second.force.csv"), written.end());
  const std::string first = test::readFile(dir / "trace.csv"), second = test::readFile(dir / "trace.second.force.csv");
  ASSERT_FALSE(second.empty());
  EXPECT_EQ(second.substr(0, second.find('\n')), kTraceHeader);
  EXPECT_NE(first, second);
  // The last rows: each burr held at its depth, k p with p = 2.5 - z (N).
  const auto lastForceZ = [](const std::string& csv) {
    const std::string row = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
    std::vector<double> values;
    size_t at = 0;
    for (int column = 0; column < 10; ++column) {
      const size_t comma = row.find(',', at);
      values.push_back(std::stod(row.substr(at, comma - at)));
      at = comma + 1;
    }
    return values[9];
  };
  EXPECT_NEAR(lastForceZ(first), 0.5, 0.05);
  EXPECT_NEAR(lastForceZ(second), 1.0, 0.05);
  const std::string summary = test::readFile(dir / "summary.json");
  const size_t tools = summary.find("\"tools\"");
  ASSERT_NE(tools, std::string::npos) << summary;
  const size_t firstEntry = summary.find("\"/first/force\"", tools), secondEntry = summary.find("\"/second/force\"", tools);
  ASSERT_NE(firstEntry, std::string::npos);
  ASSERT_NE(secondEntry, std::string::npos);
  const auto figure = [&](size_t from, const std::string& key) {
    const size_t at = summary.find("\"" + key + "\"", from);
    return std::stod(summary.substr(summary.find(':', at) + 1));
  };
  EXPECT_EQ(figure(firstEntry, "frames"), 300);
  EXPECT_EQ(figure(secondEntry, "frames"), 300);
  const double firstMax = figure(summary.find("\"force_N\"", firstEntry), "max");
  const double secondMax = figure(summary.find("\"force_N\"", secondEntry), "max");
  EXPECT_NEAR(secondMax, 2 * firstMax, 0.1 * firstMax) << "each tool's figures are its own";
  // haptics stays trace.csv's tool's.
  EXPECT_NEAR(figure(summary.find("\"force_N\"", summary.find("\"haptics\"")), "max"), firstMax, 1e-12);
  std::ostringstream printed;
  printRunSummary(*simulation, printed);
  const std::string text = printed.str();
  EXPECT_NE(text.find("tool      /first/force (trace.csv)\nhaptics   300 frames"), std::string::npos) << text;
  EXPECT_NE(text.find("tool      /second/force (trace.second.force.csv)\nhaptics   300 frames"), std::string::npos)
      << text;
}

}  // namespace
}  // namespace trephine
