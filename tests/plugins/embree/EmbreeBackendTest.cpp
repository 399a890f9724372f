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

// A tool whose shell is not a sphere (a capsule: the burr on its shaft)
// is taken point by point: held above the bone it overlaps nothing (before,
// the sphere through its farthest point, the shaft's end, overlapped the
// skull on every frame), and pressed 1 mm and slid it renders what the
// native back-end renders.
TEST(EmbreeBackendTest, ACapsuleIsTakenPointByPointAndRendersAsTheNativeBackEnd) {
  const auto summaryOf = [](const std::string& backend, const std::string& path) {
    test::TempDir dir;
    dir.write("scene.xml", R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="embree"/>
  <VoxelSkull name="skull" file="phantom:skull?voxel=0.7" backend=")" + backend + R"("/>
  <ScriptedDevice name="device" target="@skull" tipOffset="2" record="false" direction="0 0 -1" )" + path + R"(/>
  <CapsuleTool name="burr" radius="2" shaftLength="40" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2.0" maxForce="3.3"/>
</Node>)");
    std::string output;
    EXPECT_EQ(test::runProgram({"run", (dir / "scene.xml").string(), "--quiet", "--out", (dir / "run").string()},
                               &output, "env ASAN_OPTIONS=detect_leaks=0:abort_on_error=1"),
              0)
        << output;
    return test::readFile(dir / "run/summary.json");
  };
  const auto number = [](const std::string& json, const std::string& key) {
    const size_t at = json.find("\"" + key + "\"");
    EXPECT_NE(at, std::string::npos) << key;
    return std::stod(json.substr(json.find(':', at) + 1));
  };
  const std::string above = summaryOf("embree", R"(path="approach-press-slide" standoff="10" depth="-8")");
  EXPECT_NE(above.find("\"proxy_inside_frames\": 0"), std::string::npos) << above;
  EXPECT_NE(above.find("\"contact_frames\": 0"), std::string::npos) << above;
  const std::string press = R"(path="approach-press-slide" standoff="10" depth="1" slideDistance="10")";
  const std::string embree = summaryOf("embree", press), native = summaryOf("native", press);
  EXPECT_NE(embree.find("\"proxy_inside_frames\": 0"), std::string::npos) << embree;
  EXPECT_GT(number(embree, "contact_frames"), 500);
  EXPECT_NEAR(number(embree, "contact_frames"), number(native, "contact_frames"), 20);
  // The spring of a 1 mm press at 2 N/mm, on either back-end.
  EXPECT_NEAR(number(embree.substr(embree.find("\"force_N\"")), "max"), 2.0, 0.05) << embree;
  EXPECT_NEAR(number(native.substr(native.find("\"force_N\"")), "max"), 2.0, 0.05) << native;
}

}  // namespace
}  // namespace trephine::embree
