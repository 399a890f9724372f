// The integrated procedure (thesis section 6.4) on a small scene: a 3 mm
// bone plate above a soft cube. Phase 1 drills the plate and warns when the
// burr reaches the cube, with no force on it and no deformation; the tool
// change moves the proxy to a probe against the cube, which then deforms
// under it. Each phase queries only its target, and nothing drills a volume
// that is not drilled.
#include <gtest/gtest.h>

#include <cmath>

#include "framework/core/Diagnostics.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

struct Options {
  bool warning = true;
  bool drill = true;
  std::string changeEvent;  // ToolChange on this event's kind instead of at 4.2 s
};

std::string procedure(const Options& o = {}) {
  return std::string(R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  <Node name="patient">
    <VoxelSkull name="skull" file="phantom:wall?voxel=1&amp;thickness=3&amp;size=40" isovalue="400" drill=")") +
         (o.drill ? "true" : "false") + R"("/>
    <TetraBrain name="brain" file="phantom:cube?cells=4&amp;size=20" translation="0 0 -14"/>
    <TLEDForceField name="fem" mesh="@brain" dt="0.2e-3" rate="500"/>
    <FixedConstraint name="base" fem="@fem" box="-20 -20 -30 20 20 -23.9"/>
  </Node>
  <Node name="tool">
    <ScriptedDevice name="device" path="waypoints" rate="1000" buttonTimes="0.3 3.5"
                    waypoints="0 0 0 8   0.3 0 0 4   3 0 0 -2   3.5 0 0 -2   4 0 0 8
                               4.5 0 0 8   5.2 0 0 -3.5   5.6 0 0 -3.5   6 0 0 8"/>
    <PointshellTool name="burr" radius="2.5" angleStep="15" device="@device"/>
    <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
    <ToolChange name="change" )" +
         (o.changeEvent.empty() ? std::string(R"(time="4.2")") : "event=\"" + o.changeEvent + "\"") + R"( rate="1000"/>
    <GodObjectProxy name="proxy" tool="@burr" target="@/patient/skull" sweep="cylinder" drillButton="1"
                    toolChange="@change" nextTool="@probe" nextTarget="@/patient/brain" rate="1000"/>
    )" +
         (o.warning
              ? R"(<ContactWarning name="warning" proxy="@proxy" target="@/patient/brain" until="@change" rate="1000"/>)"
              : "") +
         R"(
    <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" damping="0.002" nextStiffness="0.1"
                   nextDamping="0.001" maxForce="3.3" rate="1000"/>
  </Node>
</Node>)";
}

std::unique_ptr<Simulation> run(const std::string& xml, double seconds) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = seconds;
  auto simulation = test::loadScene(xml, d, options);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (simulation) simulation->run();
  return simulation;
}

std::vector<Event> eventsOf(const Simulation& simulation, const std::string& kind) {
  std::vector<Event> found;
  for (size_t i = 0; i < simulation.events().size(); ++i)
    if (kind == simulation.events()[i].kind) found.push_back(simulation.events()[i]);
  return found;
}

std::string fact(const Simulation& simulation, const std::string& path, const std::string& name) {
  const Component* component = simulation.scene().findComponent(path);
  EXPECT_NE(component, nullptr) << path;
  std::vector<Fact> facts;
  if (component) component->reportFacts(facts);
  for (const Fact& f : facts)
    if (f.name == name) return f.value;
  ADD_FAILURE() << path << " reports no " << name;
  return "";
}

TEST(IntegratedProcedureTest, DrillingWarnsWhenTheBurrReachesTheBrainWithNoForceOnIt) {
  auto simulation = run(procedure(), 4.1);  // phase 1 only
  ASSERT_TRUE(simulation);
  EXPECT_GT(test::componentCounter(*simulation, "VoxelSkull", "breakthroughs"), 0);
  const auto warnings = eventsOf(*simulation, "contact_warning");
  ASSERT_EQ(warnings.size(), 1u);
  // The burr's bottom reaches the cube's top (z = -4) when its centre is at -1.5.
  EXPECT_GT(warnings[0].t, 1.0);
  EXPECT_LT(warnings[0].t, 3.5);
  ASSERT_TRUE(warnings[0].hasPosition());
  EXPECT_NEAR(warnings[0].position[2], -1.5, 0.6);
  // No force on the brain, no deformation, no contact of the proxy with it.
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "force_updates"), 0);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "largest_displacement_mm"), 0);
  EXPECT_EQ(test::componentCounter(*simulation, "TetraBrain", "contact_frames"), 0);
  EXPECT_EQ(test::componentCounter(*simulation, "ToolChange", "changed"), 0);
}

TEST(IntegratedProcedureTest, AfterTheToolChangeTheProbeDeformsTheBrainWithForce) {
  auto simulation = run(procedure(), 6.0);
  ASSERT_TRUE(simulation);
  const auto changes = eventsOf(*simulation, "tool_change");
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_DOUBLE_EQ(changes[0].t, 4.2);
  EXPECT_GT(test::componentCounter(*simulation, "TLEDForceField", "force_updates"), 50);
  EXPECT_GT(test::componentCounter(*simulation, "TLEDForceField", "largest_displacement_mm"), 0.3);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "non_finite_ticks"), 0);
  EXPECT_GT(test::componentCounter(*simulation, "TetraBrain", "contact_frames"), 100);
  // The force felt while pressing the brain (5.2 to 5.6 s): the softer spring, a fraction of a newton.
  double largest = 0;
  const HapticFrameLog& log = simulation->hapticLog();
  for (size_t i = 0; i < log.size(); ++i)
    if (log[i].t > 5.2 && log[i].t < 5.6) largest = std::max(largest, log[i].force.norm());
  EXPECT_GT(largest, 0.05);
  EXPECT_LT(largest, 1.0);
}

TEST(IntegratedProcedureTest, AnEventChangesToolsInTheFrameAfterItIsLogged) {
  // The burr breaking through the plate: the skull applies a frame's cut at
  // the start of the next and logs the breakthrough then, in the proxy's
  // tick; the ToolChange (earlier in the group) reads it a frame later.
  auto simulation = run(procedure({.changeEvent = "breakthrough"}), 4.1);
  ASSERT_TRUE(simulation);
  const auto breakthroughs = eventsOf(*simulation, "breakthrough");
  const auto changes = eventsOf(*simulation, "tool_change");
  ASSERT_EQ(breakthroughs.size(), 1u);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_STREQ(changes[0].detail, "event");
  EXPECT_NEAR(changes[0].t, breakthroughs[0].t + 0.001, 1e-9);
  EXPECT_LT(changes[0].t, 4.2);  // not the time of the other scenes
}

TEST(IntegratedProcedureTest, WithoutTheWarningNothingQueriesTheBrainBeforeTheChange) {
  auto without = run(procedure({.warning = false}), 4.1);
  auto with = run(procedure(), 4.1);
  ASSERT_TRUE(without && with);
  EXPECT_EQ(test::componentCounter(*without, "TetraBrain", "queries"), 0);
  // With it, one overlap query a frame while the device is valid (the warning's own count).
  EXPECT_EQ(test::componentCounter(*with, "TetraBrain", "queries"),
            test::componentCounter(*with, "ContactWarning", "queries"));
  EXPECT_GT(test::componentCounter(*with, "ContactWarning", "queries"), 4000);
}

TEST(IntegratedProcedureTest, AVolumeNotDrilledNeverChanges) {
  auto drilled = run(procedure(), 4.1);
  auto kept = run(procedure({.drill = false}), 4.1);
  ASSERT_TRUE(drilled && kept);
  EXPECT_NE(fact(*drilled, "/patient/skull", "volume_checksum_initial"),
            fact(*drilled, "/patient/skull", "volume_checksum_final"));
  EXPECT_EQ(fact(*kept, "/patient/skull", "volume_checksum_initial"),
            fact(*kept, "/patient/skull", "volume_checksum_final"));
  EXPECT_EQ(fact(*kept, "/patient/skull", "volume_checksum_initial"),
            fact(*drilled, "/patient/skull", "volume_checksum_initial"));
}

TEST(IntegratedProcedureTest, AButtonChangesToolsOnItsPress) {
  std::string xml = procedure();
  xml.replace(xml.find(R"(<ToolChange name="change" time="4.2" rate="1000"/>)"),
              std::string(R"(<ToolChange name="change" time="4.2" rate="1000"/>)").size(),
              R"(<ToolChange name="change" device="@device" button="1" rate="1000"/>)");
  auto simulation = run(xml, 1.0);  // the pedal (button 1) goes down at 0.3 s
  ASSERT_TRUE(simulation);
  EXPECT_EQ(test::componentCounter(*simulation, "ToolChange", "changed_at_s"), 0.3);
}

TEST(IntegratedProcedureTest, ToolChangeSettingsAreChecked) {
  const std::string scene = procedure();
  const auto swap = [&](const std::string& from, const std::string& to) {
    std::string xml = scene;
    xml.replace(xml.find(from), from.size(), to);
    return xml;
  };
  const std::pair<std::string, std::string> cases[] = {
      {swap(R"(time="4.2")", ""), "give exactly one of button (with device), time or event"},
      {swap(R"(time="4.2")", R"(time="4.2" button="1" device="@device")"), "give exactly one of"},
      {swap(R"(time="4.2")", R"(time="4.2" event="breakthrough")"), "give exactly one of"},
      {swap(R"(time="4.2")", R"(button="1")"), "a button needs the device"},
      {swap(R"( nextTool="@probe" nextTarget="@/patient/brain")", ""), "needs nextTool, nextTarget or both"},
      {swap(R"(toolChange="@change" )", ""), "has no effect without a toolChange"},
  };
  for (const auto& [xml, expected] : cases) {
    test::expectLoadError(xml, expected, expected);
  }
}

}  // namespace
}  // namespace trephine
