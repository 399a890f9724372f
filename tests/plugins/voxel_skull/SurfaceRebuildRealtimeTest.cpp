// A mesh back-end's drilled surface rebuilt in real time: the rebuild runs in
// its own rate group (its own thread), follows the skull's edits through
// their queue and hands copies of the surface over through the channels,
// while the haptic thread drills and queries the copy it adopted. Run under
// ThreadSanitizer in CI (label "threaded"): the rebuild touching the copy
// the haptic thread queries, or the codes it lowers, would be reported.
// Bullet stands for the mesh back-ends (Embree's worker threads are not
// instrumented).
#include <gtest/gtest.h>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

TEST(SurfaceRebuildRealtimeTest, TheRebuildHandsCopiesToTheHapticThreadWhileItDrills) {
#ifndef TREPHINE_HAS_MESH_BACKENDS
  GTEST_SKIP() << "the bullet plugin is not built";
#endif
  SimulationOptions options;
  options.realtime = true;
  options.duration = 1.0;  // s
  Diagnostics d;
  auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="bullet"/>
  <RequiredPlugin name="haptics"/>
  <Node name="patient">
    <VoxelSkull name="skull" file="phantom:halfspace?voxel=0.5&amp;density=1500&amp;size=20" isovalue="400"
                drill="true" backend="bullet"/>
    <SkullSurfaceRebuild name="rebuild" skull="@skull" rate="100"/>
  </Node>
  <ScriptedDevice name="device" record="false" path="drill-in" target="@/patient/skull" direction="0 0 -1"
                  tipOffset="2.5" standoff="3" speed="20" depth="2" feedSpeed="2.0" buttonTimes="0.1 0.9"/>
  <PointshellTool name="burr" radius="2.5" angleStep="10" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@/patient/skull" sweep="cylinder" drillButton="1"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" damping="0.002" maxForce="3.3"/>
</Node>)",
                                    d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  EXPECT_TRUE(simulation->complete());
  // The counts depend on each thread's pace (an instrumented 2-core machine
  // keeps neither): what the rebuild published is at least once adopted, and
  // the drill's edits reached it.
  EXPECT_GE(test::componentCounter(*simulation, "SkullSurfaceRebuild", "rebuilds"), 1);
  EXPECT_GT(test::componentCounter(*simulation, "SkullSurfaceRebuild", "edits_followed"), 0);
  EXPECT_EQ(test::componentCounter(*simulation, "SkullSurfaceRebuild", "edits_dropped"), 0);
  EXPECT_EQ(simulation->hapticLog().stats().nanFrames, 0u);
}

}  // namespace
}  // namespace trephine
