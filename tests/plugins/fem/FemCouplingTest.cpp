// The coupled FEM and haptic loop judged as numbers: a run repeats byte for
// byte, and smoothing the tool's force on the nodes stops the chatter of a
// spring on a soft brain. Seconds of simulation each, so the sanitizer
// presets leave them out (label numerics); FemSceneTest runs the same path
// there.
#include <gtest/gtest.h>

#include "framework/core/Diagnostics.h"
#include "tests/support/TestSupport.h"

namespace trephine::fem {
namespace {

std::unique_ptr<Simulation> runFor(const std::string& xml, double seconds, const std::filesystem::path& out) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = seconds;
  auto simulation = test::loadScene(xml, d, options);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (!simulation) return nullptr;
  simulation->run();
  std::vector<std::string> errors;
  simulation->writeOutputs(out, &errors);
  EXPECT_TRUE(errors.empty()) << errors.front();
  return simulation;
}

// The tool presses into a deforming brain (a coarse phantom of 1,200 tetrahedra, base held) and lifts.
std::string pressScene(const std::string& femAttributes = "") {
  return R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:brain?tets=1200" saveDeformed="brain_final.mesh"/>
    <TLEDForceField name="fem" mesh="@brain" dt="0.33e-3" massScaling="true" rate="1000" )" +
         femAttributes + R"(/>
    <FixedConstraint name="base" fem="@fem" box="-100 -100 -100 100 100 -45"/>
  </Node>
  <Node name="tool">
    <ScriptedDevice name="device" path="drill-in" target="@/patient/brain" direction="0 0 -1" center="10 10 0"
                    tipOffset="2.5" standoff="5" speed="20" depth="4" feedSpeed="16" rate="1000"/>
    <PointshellTool name="probe" radius="2.5" angleStep="15" device="@device"/>
    <GodObjectProxy name="proxy" tool="@probe" target="@/patient/brain" sweep="line" rate="1000"/>
    <ForceFeedback name="force" proxy="@proxy" stiffness="0.3" damping="0.001" maxForce="3.3" rate="1000"/>
  </Node>
</Node>)";
}

TEST(FemCouplingTest, SmoothingTheToolsForceStopsTheChatter) {
  // The haptic spring (0.3 N/mm) and the soft brain answer each other a frame
  // late: the force buzzes from frame to frame while pressed. With the force
  // on the nodes following the haptic loop's at 5 ms, it does not.
  test::TempDir a, b;
  auto raw = runFor(pressScene(), 0.9, a.path());
  auto smoothed = runFor(pressScene(R"(forceSmoothing="0.005")"), 0.9, b.path());
  ASSERT_TRUE(raw && smoothed);
  const double rawStep = raw->hapticLog().stats().forceStepP99;
  const double smoothStep = smoothed->hapticLog().stats().forceStepP99;
  EXPECT_GT(rawStep, 0.05);  // N
  EXPECT_LT(smoothStep, rawStep / 3);
  EXPECT_GT(smoothed->hapticLog().stats().forceMax, 0.5);  // it still presses
}

TEST(FemCouplingTest, ARunRepeatsByteForByte) {
  test::TempDir first, second;
  ASSERT_TRUE(runFor(pressScene(), 0.7, first.path()));
  ASSERT_TRUE(runFor(pressScene(), 0.7, second.path()));
  for (const char* file : {"trace.csv", "brain_final.mesh"})
    EXPECT_EQ(test::readFile(first / file), test::readFile(second / file)) << file;
}

}  // namespace
}  // namespace trephine::fem
