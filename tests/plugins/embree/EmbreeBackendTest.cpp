// The embree plugin in a scene: VoxelSkull's backend field picks it, the run
// presses and slides on the skull phantom without the proxy inside the bone,
// the summary names the back-end, and the thesis's removal law (which cuts
// the voxels the native back-end's contacts touch) is refused at load. Its
// answers to the queries are held to closed forms with every other back-end
// in tests/plugins/voxel_skull/VoxelBackendConformanceTest.cpp.
#include <gtest/gtest.h>

#include "tests/support/TestSupport.h"

namespace trephine::embree {
namespace {

std::string skullScene(const std::string& skullAttributes) {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="embree"/>
  <VoxelSkull name="skull" file="phantom:skull?voxel=3" backend="embree" )" +
         skullAttributes + R"(/>
  <ScriptedDevice name="device" target="@skull" tipOffset="2.5" record="false" path="approach-press-slide"
                  direction="0 0 -1" depth="1" slideDistance="5"/>
  <PointshellTool name="burr" radius="2.5" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull" sweep="spheres"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" maxForce="3.3"/>
</Node>)";
}

TEST(EmbreeBackendTest, AScenePicksItByTheBackendFieldAndTheThesisLawIsRefused) {
  // Pressed 1 mm into the skull phantom and slid: the spring of the press,
  // never inside, and the summary names the back-end.
  test::TempDir dir;
  dir.write("scene.xml", skullScene(""));
  std::string output;
  // Under AddressSanitizer, LeakSanitizer's own tracer (which stops every
  // thread to scan it) dies with SIGSEGV at random at the exit of a process
  // with Embree's worker threads, found no leak, and fails the run: the
  // program's leak check is off here (this test's own process keeps its).
  ASSERT_EQ(test::runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--out", (dir / "run").string()},
                             &output, "env ASAN_OPTIONS=detect_leaks=0:abort_on_error=1"),
            0)
      << output;
  const std::string summary = test::readFile(dir / "run/summary.json");
  EXPECT_NE(summary.find("\"backend\": \"embree\""), std::string::npos);
  EXPECT_NE(summary.find("\"proxy_inside_frames\": 0"), std::string::npos) << summary;

  Diagnostics d;
  EXPECT_FALSE(test::loadScene(skullScene(R"(drill="true" removal="thesis")"), d));
  EXPECT_NE(test::messages(d).find("removal=\"thesis\" cuts the voxels the native back-end's contacts touch"),
            std::string::npos)
      << test::messages(d);
}

}  // namespace
}  // namespace trephine::embree
