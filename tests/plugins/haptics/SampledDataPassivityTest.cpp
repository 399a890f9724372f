// The sampled-data passivity check: the condition itself, the warning at the
// renderer's stiffness when a scene breaks it, and --strict making it an error
// (through Simulation, and through the program as a user runs it).
#include <gtest/gtest.h>

#include "plugins/haptics/SampledDataPassivity.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

TEST(SampledDataPassivityTest, PassiveExactlyWhenTheDeviceDampingExceedsKTOver2PlusB) {
  // k = 3 N/mm, B = 0.002 N s/mm at 1 kHz need b > 0.0015 + 0.002 = 0.0035 N s/mm.
  const auto held = haptics::sampledDataPassivity(3.0, 0.002, 1000.0, 0.00645);
  EXPECT_TRUE(held.passive);
  EXPECT_NEAR(held.requiredDamping, 0.0035, 1e-15);
  EXPECT_NEAR(held.largestStiffness, 2.0 * (0.00645 - 0.002) * 1000.0, 1e-12);  // 8.9 N/mm
  EXPECT_FALSE(haptics::sampledDataPassivity(3.0, 0.002, 1000.0, 0.0035).passive) << "the bound itself is not enough";
  EXPECT_TRUE(haptics::sampledDataPassivity(3.0, 0.002, 1000.0, 0.0035 + 1e-9).passive);
  // A negative virtual damping costs as much as a positive one.
  EXPECT_NEAR(haptics::sampledDataPassivity(3.0, -0.002, 1000.0, 0.0).requiredDamping, 0.0035, 1e-15);
  // Faster rendering allows stiffer walls: at 4 kHz, 4 times.
  EXPECT_NEAR(haptics::sampledDataPassivity(1.0, 0.0, 4000.0, 0.00645).largestStiffness, 4.0 * 12.9, 1e-9);
  // No stiffness is passive when the virtual damping alone exceeds the device's.
  EXPECT_EQ(haptics::sampledDataPassivity(0.0, 0.01, 1000.0, 0.00645).largestStiffness, 0.0);
}

// Line 6 holds the renderer; its stiffness value starts at column 57.
std::string scene(const std::string& device, const std::string& stiffness = "20") {
  return R"(<Node name="root">
  <RequiredPlugin name="voxel_skull"/>
  <RequiredPlugin name="haptics"/>
  <VoxelSkull name="skull" file="phantom:halfspace?voxel=0.5" isovalue="500"/>
  <PointshellTool name="burr" radius="2.5" angleStep="10" device="@hand"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness=")" + stiffness + R"(" damping="0"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@skull"/>
  <ScriptedDevice name="intent" path="waypoints" record="false" waypoints="0 0 0 5  0.1 0 0 5"/>
  )" + device +
         R"(
</Node>)";
}
const std::string kHand = R"(<HandDevice name="hand" intent="@intent" record="false"/>)";
const std::string kWarning =
    "stiffness of ForceFeedback 'force': stiffness 20 N/mm with damping 0 N s/mm at 1000 Hz needs a physical "
    "damping above 0.01 N s/mm; /hand has 0.00645 (deviceDamping + gripDamping): largest passive stiffness 12.9 N/mm";

TEST(SampledDataPassivityTest, ANonPassiveRenderingIsAWarningAtItsStiffness) {
  Diagnostics d;
  auto simulation = test::loadScene(scene(kHand), d, {}, "hand.xml");
  ASSERT_TRUE(simulation) << "a warning does not stop the run\n" << test::messages(d);
  ASSERT_EQ(d.all().size(), 1u) << test::messages(d);
  const Diagnostic& warning = d.all()[0];
  EXPECT_EQ(warning.severity, Severity::Warning);
  EXPECT_EQ(warning.where.str(), "hand.xml:6:57");
  EXPECT_EQ(warning.message.rfind(kWarning, 0), 0u) << warning.message;
  EXPECT_FALSE(d.hasErrors());
}

TEST(SampledDataPassivityTest, StrictMakesTheWarningAnError) {
  Diagnostics d;
  SimulationOptions options;
  options.strict = true;
  EXPECT_FALSE(test::loadScene(scene(kHand), d, options, "hand.xml"));
  ASSERT_EQ(d.errorCount(), 1) << test::messages(d);
  EXPECT_EQ(d.all()[0].where.str(), "hand.xml:6:57");
  EXPECT_NE(d.all()[0].message.find("(an error with --strict)"), std::string::npos) << d.all()[0].message;
}

TEST(SampledDataPassivityTest, DevicesWithoutDynamicsAreJudgedAgainstAGenerousDevice) {
  // A scripted device stands for a real one: a rendering that a device with
  // 0.01 N s/mm of its own damping keeps passive (15 N/mm, no virtual damping,
  // at 1 kHz: b > 0.0075) loads without a word, even with --strict.
  const std::string scripted = R"(<ScriptedDevice name="hand" path="waypoints" record="false" waypoints="0 0 0 5"/>)";
  Diagnostics quiet;
  SimulationOptions options;
  options.strict = true;
  EXPECT_TRUE(test::loadScene(scene(scripted, "15"), quiet, options)) << test::messages(quiet);
  EXPECT_TRUE(quiet.all().empty()) << test::messages(quiet);
  // 300 N/mm (300 N/m, typed as N/mm, is the slip) would chatter between 0
  // and the force limit every frame: warned, at the stiffness, with the bound.
  Diagnostics d;
  EXPECT_TRUE(test::loadScene(scene(scripted, "300"), d, {}, "scripted.xml"));
  ASSERT_EQ(d.all().size(), 1u) << test::messages(d);
  EXPECT_EQ(d.all()[0].severity, Severity::Warning);
  EXPECT_EQ(d.all()[0].where.str(), "scripted.xml:6:57");
  EXPECT_NE(d.all()[0].message.find("stiffness 300 N/mm with damping 0 N s/mm at 1000 Hz needs a physical damping "
                                    "above 0.15 N s/mm"),
            std::string::npos)
      << d.all()[0].message;
  EXPECT_NE(d.all()[0].message.find("largest passive stiffness 20 N/mm"), std::string::npos) << d.all()[0].message;
  EXPECT_NE(d.all()[0].message.find("is it in N/m"), std::string::npos) << d.all()[0].message;
}

TEST(SampledDataPassivityTest, TheProgramPrintsTheWarningAndStrictExitsOne) {
  test::TempDir dir;
  const auto file = dir.write("hand.xml", scene(kHand)).string();
  std::string out;
  EXPECT_EQ(test::runProgram({"validate", file}, &out), 0) << out;
  EXPECT_NE(out.find(file + ":6:57: warning: " + kWarning), std::string::npos) << out;
  EXPECT_NE(out.find("ok"), std::string::npos) << out;

  EXPECT_EQ(test::runProgram({"validate", file, "--strict"}, &out), 1) << out;
  EXPECT_NE(out.find(file + ":6:57: error: " + kWarning), std::string::npos) << out;

  const std::string runs = (dir / "run").string();
  EXPECT_EQ(test::runProgram({"run", file, "--strict", "--out", runs, "--quiet"}, &out), 1) << out;
  EXPECT_FALSE(std::filesystem::exists(dir / "run" / "summary.json")) << "nothing ran";
  EXPECT_EQ(test::runProgram({"run", file, "--out", runs, "--quiet"}, &out), 0) << out;
  EXPECT_NE(out.find("warning: "), std::string::npos) << out;
  EXPECT_TRUE(std::filesystem::exists(dir / "run" / "summary.json"));
}

}  // namespace
}  // namespace trephine
