// A deforming brain in real time: the deformation runs in its own rate group
// (its own thread) and the haptic group reads the node positions it publishes
// through the channel; the grids rebuilt on the deformed shape come from a
// third. Run under ThreadSanitizer in CI (label "threaded"): a
// haptic frame reading a slot the deformation is writing would be reported.
// Cube phantoms (no meshing): the ThreadSanitizer build leaves the CGAL
// mesher out.
#include <gtest/gtest.h>

#include "tests/support/BrainProbe.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

SimulationOptions realtimeForOneSecond() {
  SimulationOptions options;
  options.realtime = true;
  options.duration = 1.0;  // s
  return options;
}

TEST(DeformingBrainRealtimeTest, TheHapticGroupReadsTheDeformationsPositionsAcrossThreads) {
  const SimulationOptions options = realtimeForOneSecond();
  Diagnostics d;
  // A cube of 2,560 tetrahedra: under ThreadSanitizer a rebuild of 11,000
  // takes 150 ms, the adopted grids fall behind the wave, every haptic query
  // widens and the haptic thread keeps a tenth of its frames.
  auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=8"/>
    <ScriptedDeformation name="wave" mesh="@brain" amplitude="6" wavelength="150" center="5 5 100" period="0.5"
                         rate="250"/>
    <TetGridRebuild name="grids" mesh="@brain" threshold="0.25" rate="100"/>
  </Node>
  )" + test::brainProbeNode(R"(path="pokes" center="5 5 0" standoff="3" depth="2" speed="40")") +
                                        R"(
</Node>)",
                                    d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  ASSERT_EQ(simulation->scheduler().groups().size(), 3u) << "haptic, deformation and grid threads";
  simulation->run();
  EXPECT_TRUE(simulation->complete()) << simulation->incompleteReason();
  const HapticStats s = simulation->hapticLog().stats();
  EXPECT_EQ(s.nanFrames, 0u);
  EXPECT_GT(s.contactFrames, 50u);
  // The brain took new shapes from the other thread (about 250 of them when
  // both keep their pace), never more than were published: counts relative
  // to what the other thread did, since a loaded or instrumented machine
  // keeps neither thread's pace.
  const double taken = test::componentCounter(*simulation, "TetraBrain", "deformation_frames");
  const double published = test::componentCounter(*simulation, "ScriptedDeformation", "published_steps");
  EXPECT_GE(taken, 10.0);
  EXPECT_LE(taken, published);
  // And grids built on the deformed shape in a third thread, adopted by the haptic one.
  EXPECT_GE(test::componentCounter(*simulation, "TetGridRebuild", "rebuilds"), 2.0);
  EXPECT_GE(test::componentCounter(*simulation, "TetraBrain", "adopted_grids"), 2.0);
}

TEST(DeformingBrainRealtimeTest, TheFemRunsInAThreadOfItsOwnBesideTheHapticLoop) {
  // The FEM at the haptic rate but in its own group (group="fem"): two
  // threads at 1 kHz exchanging node positions and node forces through channels.
  const SimulationOptions options = realtimeForOneSecond();
  Diagnostics d;
  auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="fem"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=8&amp;size=90"/>
    <TLEDForceField name="fem" mesh="@brain" dt="0.33e-3" massScaling="true" rate="1000" group="fem"/>
    <FixedConstraint name="base" fem="@fem" box="-100 -100 -100 100 100 -44"/>
  </Node>
  )" + test::brainProbeNode(R"(path="drill-in" center="10 10 0" standoff="3" speed="20" depth="4" feedSpeed="16")") +
                                        R"(
</Node>)",
                                    d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  ASSERT_EQ(simulation->scheduler().groups().size(), 2u) << "the haptic thread and the FEM's";
  simulation->run();
  EXPECT_TRUE(simulation->complete()) << simulation->incompleteReason();
  EXPECT_EQ(simulation->hapticLog().stats().nanFrames, 0u);
  // Counts that hold on a loaded machine too (about 400 contact frames and
  // 1000 shapes when the threads keep their pace; 41 shapes were seen under
  // ThreadSanitizer on a loaded 2-core machine): the exchange went both ways,
  // repeatedly, and the brain never took more shapes than the FEM published.
  EXPECT_GT(simulation->hapticLog().stats().contactFrames, 20u);
  EXPECT_GT(test::componentCounter(*simulation, "TLEDForceField", "force_updates"), 5.0);
  const double taken = test::componentCounter(*simulation, "TetraBrain", "deformation_frames");
  EXPECT_GE(taken, 10.0);
  EXPECT_LE(taken, test::componentCounter(*simulation, "TLEDForceField", "published_steps"));
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "non_finite_ticks"), 0.0);
}

}  // namespace
}  // namespace trephine
