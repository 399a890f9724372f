// The bullet plugin in a scene: VoxelSkull's backend field picks it, the run
// presses and slides on the skull phantom without the proxy inside the bone,
// the summary names the back-end, Bullet's queries allocate (through its own
// allocator, counted) next to nothing in thousands of queries, and a burr on
// a shaft (CapsuleTool) is taken too, its shaft a Bullet cylinder. Its answers to
// the queries are held to closed forms with every other back-end in
// tests/plugins/voxel_skull/VoxelBackendConformanceTest.cpp.
#include <gtest/gtest.h>

#include "tests/support/TestSupport.h"

namespace trephine::bullet {
namespace {

std::string skullScene(const std::string& tool) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="bullet"/>
  <VoxelSkull name="skull" file="phantom:skull?voxel=3" backend="bullet"/>
  <ScriptedDevice name="device" target="@skull" tipOffset="2.5" record="false" path="approach-press-slide"
                  direction="0 0 -1" depth="1" slideDistance="5"/>
  )" + tool +
         R"(
  <GodObjectProxy name="proxy" tool="@burr" target="@skull" sweep="spheres"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" maxForce="3.3"/>
</Node>)";
}

TEST(BulletBackendTest, AScenePicksItAndItsQueriesAllocateNextToNothing) {
  const auto simulation = test::runScene(skullScene(R"(<PointshellTool name="burr" radius="2.5" device="@device"/>)"));
  ASSERT_TRUE(simulation);
  ASSERT_TRUE(simulation->complete()) << simulation->incompleteReason();
  const HapticStats stats = simulation->hapticLog().stats();
  EXPECT_GT(stats.contactFrames, 500u) << "pressed and slid on the bone";
  EXPECT_EQ(stats.proxyInsideFrames, 0u);
  EXPECT_EQ(stats.nanFrames, 0u);
  // Pressed 1 mm in with k = 2 N/mm: about 2 N, whatever the back-end.
  EXPECT_GT(stats.forceMax, 1.5);
  const double queries = test::componentCounterAt(*simulation, "/skull", "queries");
  EXPECT_GT(queries, 1000);
  // Bullet's pools are made when the world is; a query may still grow an
  // array the first time (one allocation of 31 bytes measured).
  EXPECT_LE(test::componentCounterAt(*simulation, "/skull", "query_allocations"), 4) << queries << " queries";

  test::TempDir dir;
  dir.write("scene.xml", skullScene(R"(<PointshellTool name="burr" radius="2.5" device="@device"/>)"));
  std::string output;
  ASSERT_EQ(
      test::runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--out", (dir / "run").string()}, &output), 0)
      << output;
  EXPECT_NE(test::readFile(dir / "run/summary.json").find("\"backend\": \"bullet\""), std::string::npos);
}

TEST(BulletBackendTest, ABurrOnAShaftPressesAndSlidesOnTheSkull) {
  // The shaft tilted 60 degrees from the vertical, so that it reaches down
  // to the bone beside the burr as the burr presses in.
  const auto simulation = test::runScene(skullScene(
      R"(<CapsuleTool name="burr" radius="2.5" shaftRadius="1" shaftLength="20" axis="0.866 0 0.5" device="@device"/>)"));
  ASSERT_TRUE(simulation);
  ASSERT_TRUE(simulation->complete()) << simulation->incompleteReason();
  const HapticStats stats = simulation->hapticLog().stats();
  EXPECT_GT(stats.contactFrames, 500u);
  EXPECT_EQ(stats.proxyInsideFrames, 0u);
  EXPECT_EQ(stats.nanFrames, 0u);
  EXPECT_GT(stats.forceMax, 1.5);
  EXPECT_LE(stats.forceStepMax, 0.5) << "N per frame";
}

}  // namespace
}  // namespace trephine::bullet
