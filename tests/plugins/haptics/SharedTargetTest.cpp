// Two tools on one target (the suction and bipolar of a neurosurgeon's two
// hands, two burrs on one bone): whichever order the scene file lists them
// in, each tool feels the same force frame by frame, the brain deforms the
// same and the skull loses the same bone. The target answers each tool's
// query with a value, adds the tools' forces up, refreshes once a frame and
// applies the cuts of a frame together at the start of the next; nothing
// depends on which tool ticked first. Run on every collision back-end built.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "framework/core/Diagnostics.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

std::vector<std::string> backends() {
  std::vector<std::string> names{"native"};
#ifdef TREPHINE_TEST_EMBREE
  names.push_back("embree");
#endif
#ifdef TREPHINE_TEST_BULLET
  names.push_back("bullet");
#endif
  return names;
}

std::string requiredPlugin(const std::string& backend) {
  return backend == "native" ? "" : "<RequiredPlugin name=\"" + backend + "\"/>";
}

// One hand: a device following `waypoints` (t x y z), a pointshell tool, its
// proxy against `target` and its force feedback.
std::string hand(const std::string& name, const std::string& waypoints, const std::string& target,
                 const std::string& stiffness) {
  // The run's trace.csv is one tool's; both are recorded below.
  return R"(<Node name=")" + name + R"(">
    <ScriptedDevice name="device" path="waypoints" rate="1000" waypoints=")" +
         waypoints + R"("/>
    <PointshellTool name="tool" radius="2.5" angleStep="15" device="@device"/>
    <GodObjectProxy name="proxy" tool="@tool" target=")" +
         target + R"(" sweep="cylinder" rate="1000"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness=")" +
         stiffness + R"(" damping="0.001" maxForce="3.3" trace="false" rate="1000"/>
  </Node>
  )";
}

std::string recorders() {
  return R"(<Node name="record">
    <Recorder name="left" source="@/left/force" rate="1000" file="left.csv"/>
    <Recorder name="right" source="@/right/force" rate="1000" file="right.csv"/>
  </Node>)";
}

// Both probes press the soft cube (top at z = 10) at once, 6 mm apart, and
// slide towards each other; each force is spread over the nodes within
// 8 mm, so the two reach nodes they share.
std::string brainScene(const std::string& backend, bool leftFirst) {
  const std::string left =
      hand("left", "0 -3 0 14   0.3 -3 0 10.8   0.6 -1.5 1 10.6   0.8 -3 0 14", "@/patient/brain", "0.3");
  const std::string right =
      hand("right", "0 3 0 14   0.25 3 0 11   0.55 1.5 -1 10.7   0.8 3 0 14", "@/patient/brain", "0.3");
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  )" + requiredPlugin(backend) +
         R"(
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=6&amp;size=20" backend=")" +
         backend + R"(" forceSpread="8" saveDeformed="brain.vtu"/>
    <TLEDForceField name="fem" mesh="@brain" dt="0.2e-3" rate="500"/>
    <FixedConstraint name="base" fem="@fem" box="-20 -20 -30 20 20 -9.9"/>
  </Node>
  )" + (leftFirst ? left + right : right + left) +
         recorders() + "\n</Node>";
}

// Both burrs drill the 3 mm plate 4 mm apart (their footprints overlap), one
// pressing harder and starting later.
std::string skullScene(const std::string& backend, bool leftFirst) {
  const std::string left = hand("left", "0 -2 0 6   0.1 -2 0 3.5   0.6 -2 0 0   0.7 -2 0 6", "@/patient/skull", "2");
  const std::string right = hand("right", "0 2 0 6   0.15 2 0 3.5   0.6 2 0 -0.5   0.7 2 0 6", "@/patient/skull", "2.5");
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  )" + requiredPlugin(backend) +
         R"(
  <Node name="patient">
    <VoxelSkull name="skull" file="phantom:wall?voxel=1&amp;thickness=3&amp;size=16" isovalue="400" drill="true"
                backend=")" +
         backend + R"(" saveDrilled="drilled.mha"/>
  </Node>
  )" + (leftFirst ? left + right : right + left) +
         recorders() + "\n</Node>";
}

struct Outcome {
  std::string left, right;  // each tool's recorded samples (force, proxy, penetration) frame by frame
  std::string saved;        // the target's saved shape (deformed mesh, drilled volume)
  double targetFigure = 0;
};

Outcome run(const std::string& xml, const std::string& savedName, const std::string& type, const std::string& figure) {
  test::TempDir dir;
  Diagnostics d;
  SimulationOptions options;
  options.outputDirectory = dir.path();
  auto simulation = test::loadScene(xml, d, options);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (!simulation) return {};
  simulation->run();
  simulation->writeOutputs(dir.path());
  return {test::readFile(dir / "left.csv"), test::readFile(dir / "right.csv"), test::readFile(dir / savedName),
          test::componentCounter(*simulation, type, figure)};
}

// Rows of a recording in which the force is not zero.
int pressingRows(const std::string& csv) {
  int rows = 0;
  size_t start = csv.find('\n') + 1;
  while (start < csv.size()) {
    const size_t end = csv.find('\n', start);
    const std::string row = csv.substr(start, end - start);
    // Columns: t, source_t, device xyz, proxy xyz, force xyz, ...
    std::vector<double> values;
    size_t at = 0;
    while (at <= row.size() && values.size() < 11) {
      const size_t comma = row.find(',', at);
      values.push_back(std::stod(row.substr(at, comma - at)));
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
    if (values.size() == 11 && (values[8] != 0 || values[9] != 0 || values[10] != 0)) ++rows;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return rows;
}

class SharedTargetTest : public testing::TestWithParam<std::string> {};

TEST_P(SharedTargetTest, TwoProbesOnOneBrainFeelAndDeformTheSameInEitherOrder) {
  const Outcome a = run(brainScene(GetParam(), true), "brain.vtu", "TLEDForceField", "force_updates");
  const Outcome b = run(brainScene(GetParam(), false), "brain.vtu", "TLEDForceField", "force_updates");
  // Both press, for a good part of the run, and the brain takes their forces.
  EXPECT_GT(pressingRows(a.left), 60);
  EXPECT_GT(pressingRows(a.right), 60);
  EXPECT_GT(a.targetFigure, 40);
  EXPECT_EQ(a.left, b.left) << "the left probe's samples depend on the scene's order";
  EXPECT_EQ(a.right, b.right) << "the right probe's samples depend on the scene's order";
  EXPECT_FALSE(a.saved.empty());
  EXPECT_EQ(a.saved, b.saved) << "the deformed brain depends on the scene's order";
}

TEST_P(SharedTargetTest, TwoBurrsOnOneSkullCutTheSameBoneInEitherOrder) {
  const Outcome a = run(skullScene(GetParam(), true), "drilled.mha", "VoxelSkull", "voxels_removed");
  const Outcome b = run(skullScene(GetParam(), false), "drilled.mha", "VoxelSkull", "voxels_removed");
  EXPECT_GT(pressingRows(a.left), 200);
  EXPECT_GT(pressingRows(a.right), 200);
  // 35 voxels on the native back-end, 20 on the mesh ones (which see a smoother surface).
  EXPECT_GT(a.targetFigure, 10) << "both burrs drill";
  EXPECT_EQ(a.targetFigure, b.targetFigure);
  EXPECT_EQ(a.left, b.left) << "the left burr's samples depend on the scene's order";
  EXPECT_EQ(a.right, b.right) << "the right burr's samples depend on the scene's order";
  EXPECT_FALSE(a.saved.empty());
  EXPECT_EQ(a.saved, b.saved) << "the drilled volume depends on the scene's order";
}

INSTANTIATE_TEST_SUITE_P(Backends, SharedTargetTest, testing::ValuesIn(backends()),
                         [](const testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace trephine
