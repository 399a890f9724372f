// Two to four tools on one target (the suction and bipolar of a
// neurosurgeon's two hands, burrs on one bone), as a property: whatever order
// the scene file lists them in (the identity, reversed, random permutations),
// every tool's trace (trace.csv and each trace.PATH.csv), the deformed brain
// and the drilled skull are the same to the bit. On every collision back-end
// built, every search of the brain (previous-contact keeps its start per
// tool), both removal laws of the skull, and with two tools whose forces are
// equal (both pressed to the force clamp on a flat face: a sort of the
// responses by value would leave their order to std::sort). The contact
// frame begins each target once a frame, each tool queries with its own
// memory, and the target takes the frame's responses in one call in the
// order of the renderers' paths: nothing depends on which tool ticked first.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <random>
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
// proxy against `target` and its force feedback; /t0 writes trace.csv, the
// others their trace.tN.force.csv.
std::string hand(int index, const std::string& waypoints, const std::string& target, const std::string& stiffness) {
  const std::string name = "t" + std::to_string(index);
  return R"(<Node name=")" + name + R"(">
    <ScriptedDevice name="device" path="waypoints" rate="1000" waypoints=")" +
         waypoints + R"("/>
    <PointshellTool name="tool" radius="2.5" angleStep="15" device="@device"/>
    <GodObjectProxy name="proxy" tool="@tool" target=")" +
         target + R"(" sweep="cylinder" rate="1000"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness=")" +
         stiffness + R"(" damping="0.001" maxForce="3.3" trace=")" + (index == 0 ? "true" : "false") +
         R"(" rate="1000"/>
  </Node>
  )";
}

// The hands in the order `order` lists their indices.
std::string hands(const std::vector<std::string>& all, const std::vector<int>& order) {
  std::string text;
  for (const int i : order) text += all[size_t(i)];
  return text;
}

// On the soft cube (top at z = 10): t0 and t1 press straight down on the flat
// top, hard enough to reach the force clamp (equal forces), 8 mm apart; t2
// and t3 press and slide towards each other. Each force is spread over the
// nodes within 8 mm, so the tools reach nodes they share.
std::vector<std::string> brainHands() {
  const std::string brain = "@/patient/brain";
  return {hand(0, "0 -4 -4 14   0.3 -4 -4 9.5   0.6 -4 -4 9.4   0.8 -4 -4 14", brain, "2"),
          hand(1, "0 4 -4 14   0.3 4 -4 9.5   0.6 4 -4 9.4   0.8 4 -4 14", brain, "2"),
          hand(2, "0 -3 4 14   0.3 -3 4 10.8   0.6 -1.5 5 10.6   0.8 -3 4 14", brain, "0.3"),
          hand(3, "0 3 4 14   0.25 3 4 11   0.55 1.5 3 10.7   0.8 3 4 14", brain, "0.3")};
}

std::string brainScene(const std::string& backend, const std::string& search, const std::vector<int>& order) {
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  )" + requiredPlugin(backend) +
         R"(
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=6&amp;size=20" backend=")" +
         backend + R"(" )" + (search.empty() ? "" : "search=\"" + search + "\" ") +
         R"(forceSpread="8" saveDeformed="brain.vtu"/>
    <TLEDForceField name="fem" mesh="@brain" dt="0.2e-3" rate="500"/>
    <FixedConstraint name="base" fem="@fem" box="-20 -20 -30 20 20 -9.9"/>
  </Node>
  )" + hands(brainHands(), order) +
         "\n</Node>";
}

// Burrs drilling the 3 mm plate (top at z = 1.5): t0 and t1 pressed to the
// clamp 6 mm apart (equal forces), t2 and t3 with footprints overlapping
// theirs, one pressing harder and starting later.
std::vector<std::string> skullHands() {
  const std::string skull = "@/patient/skull";
  return {hand(0, "0 -3 -3 6   0.1 -3 -3 3.5   0.6 -3 -3 0   0.7 -3 -3 6", skull, "2"),
          hand(1, "0 3 -3 6   0.1 3 -3 3.5   0.6 3 -3 0   0.7 3 -3 6", skull, "2"),
          hand(2, "0 -2 1 6   0.1 -2 1 3.5   0.6 -2 1 0   0.7 -2 1 6", skull, "2"),
          hand(3, "0 2 1 6   0.15 2 1 3.5   0.6 2 1 -0.5   0.7 2 1 6", skull, "2.5")};
}

std::string skullScene(const std::string& backend, const std::string& removal, const std::vector<int>& order) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  )" + requiredPlugin(backend) +
         R"(
  <Node name="patient">
    <VoxelSkull name="skull" file="phantom:wall?voxel=1&amp;thickness=3&amp;size=16" isovalue="400" drill="true"
                removal=")" +
         removal + R"(" backend=")" + backend + R"(" saveDrilled="drilled.mha"/>
  </Node>
  )" + hands(skullHands(), order) +
         "\n</Node>";
}

struct Outcome {
  std::map<std::string, std::string> traces;  // each tool's trace file by name
  std::string saved;                          // the target's saved shape (deformed mesh, drilled volume)
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
  Outcome outcome;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("trace.", 0) == 0) outcome.traces[name] = test::readFile(entry.path());
  }
  outcome.saved = test::readFile(dir / savedName);
  outcome.targetFigure = test::componentCounter(*simulation, type, figure);
  return outcome;
}

// Rows of a trace in which the force is not zero (columns 7 to 9: force x y z).
int pressingRows(const std::string& csv) {
  int rows = 0;
  size_t start = csv.find('\n') + 1;
  while (start < csv.size()) {
    const size_t end = csv.find('\n', start);
    const std::string row = csv.substr(start, end - start);
    std::vector<double> values;
    size_t at = 0;
    while (values.size() < 10) {
      const size_t comma = row.find(',', at);
      values.push_back(std::stod(row.substr(at, comma - at)));
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
    if (values.size() == 10 && (values[7] != 0 || values[8] != 0 || values[9] != 0)) ++rows;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return rows;
}

// The orders tried for `count` tools: as listed, reversed, and two random
// permutations (seeded by `seed`, so a failure comes back).
std::vector<std::vector<int>> orders(int count, unsigned seed) {
  std::vector<int> identity(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) identity[size_t(i)] = i;
  std::vector<std::vector<int>> all{identity, std::vector<int>(identity.rbegin(), identity.rend())};
  std::mt19937 random(seed);
  for (int k = 0; k < 2; ++k) {
    std::vector<int> shuffled = identity;
    std::shuffle(shuffled.begin(), shuffled.end(), random);
    all.push_back(shuffled);
  }
  return all;
}

std::string orderText(const std::vector<int>& order) {
  std::string text;
  for (const int i : order) text += (text.empty() ? "t" : ", t") + std::to_string(i);
  return text;
}

void expectSameOutcomes(const std::vector<Outcome>& outcomes, const std::vector<std::vector<int>>& tried,
                        size_t tools) {
  ASSERT_FALSE(outcomes.empty());
  const Outcome& first = outcomes.front();
  // Every tool writes a trace: trace.csv and one trace.tN.force.csv for each other tool.
  ASSERT_EQ(first.traces.size(), tools);
  EXPECT_TRUE(first.traces.count("trace.csv"));
  for (size_t i = 1; i < tools; ++i) EXPECT_TRUE(first.traces.count("trace.t" + std::to_string(i) + ".force.csv"));
  for (const auto& [name, trace] : first.traces) EXPECT_GT(pressingRows(trace), 60) << name << ": the tool presses";
  EXPECT_FALSE(first.saved.empty());
  for (size_t k = 1; k < outcomes.size(); ++k) {
    SCOPED_TRACE("listed as " + orderText(tried[k]) + " against " + orderText(tried[0]));
    for (const auto& [name, trace] : first.traces) {
      const auto other = outcomes[k].traces.find(name);
      ASSERT_NE(other, outcomes[k].traces.end()) << name;
      EXPECT_TRUE(other->second == trace) << name << " depends on the order the tools are listed in";
    }
    EXPECT_TRUE(outcomes[k].saved == first.saved) << "the target's saved shape depends on the order";
    EXPECT_EQ(outcomes[k].targetFigure, first.targetFigure);
  }
}

class SharedTargetTest : public testing::TestWithParam<std::string> {};

TEST_P(SharedTargetTest, ToolsOnOneBrainFeelAndDeformTheSameInAnyOrder) {
  const std::vector<std::string> searches =
      GetParam() == "native" ? std::vector<std::string>{"grid", "first-tetrahedron", "previous-contact"}
                             : std::vector<std::string>{""};  // the mesh back-ends have one search
  for (size_t s = 0; s < searches.size(); ++s) {
    SCOPED_TRACE("search " + (searches[s].empty() ? GetParam() + "'s" : searches[s]));
    const int tools = 2 + int((s + GetParam().size()) % 3);  // two to four
    const std::vector<std::vector<int>> tried = orders(tools, unsigned(17 + s));
    std::vector<Outcome> outcomes;
    for (const std::vector<int>& order : tried)
      outcomes.push_back(run(brainScene(GetParam(), searches[s], order), "brain.vtu", "TLEDForceField", "force_updates"));
    EXPECT_GT(outcomes.front().targetFigure, 40) << "the brain takes the tools' forces";
    expectSameOutcomes(outcomes, tried, size_t(tools));
  }
}

TEST_P(SharedTargetTest, BurrsOnOneSkullCutTheSameBoneInAnyOrder) {
  // The thesis's law cuts the voxels the native back-end's contacts touch.
  const std::vector<std::string> removals =
      GetParam() == "native" ? std::vector<std::string>{"force", "thesis"} : std::vector<std::string>{"force"};
  for (size_t r = 0; r < removals.size(); ++r) {
    SCOPED_TRACE("removal " + removals[r]);
    const int tools = 2 + int((r + GetParam().size() + 1) % 3);
    const std::vector<std::vector<int>> tried = orders(tools, unsigned(29 + r));
    std::vector<Outcome> outcomes;
    for (const std::vector<int>& order : tried)
      outcomes.push_back(run(skullScene(GetParam(), removals[r], order), "drilled.mha", "VoxelSkull", "voxels_removed"));
    EXPECT_GT(outcomes.front().targetFigure, 10) << "the burrs drill";
    expectSameOutcomes(outcomes, tried, size_t(tools));
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, SharedTargetTest, testing::ValuesIn(backends()),
                         [](const testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace trephine
