// TetGridRebuild: the native back-end's grids built again on the deformed
// shape off the haptic thread. The grids change the cost of the queries,
// never their answers: a run with rebuilds gives the same trace byte for byte
// as one without, while the frames whose deformation is beyond the grids'
// margin (the slow, widened queries) all but vanish.
#include <gtest/gtest.h>

#include "framework/core/Diagnostics.h"
#include "tests/support/BrainProbe.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

// A 200 mm cube (25 mm cells, a margin of about 7.8 mm) through which a wave
// of 20 mm runs while a probe pokes it.
std::string wavingCube(bool rebuild) {
  return std::string(R"(<Node name="root">
  <RequiredPlugin name="tetra_brain"/>
  <RequiredPlugin name="haptics"/>
  <Node name="patient">
    <TetraBrain name="brain" file="phantom:cube?cells=8"/>
    <ScriptedDeformation name="wave" mesh="@brain" amplitude="20" wavelength="250" center="5 5 100" period="2"
                         rate="250"/>
    )") + (rebuild ? R"(<TetGridRebuild name="grids" mesh="@brain" rate="100"/>)" : "") +
         R"(
  </Node>
  )" + test::brainProbeNode(R"(path="pokes" center="5 5 0" standoff="3" depth="2" speed="40")") +
         R"(
</Node>)";
}

std::unique_ptr<Simulation> runInto(const std::string& xml, const std::filesystem::path& out) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = 1.0;
  auto simulation = test::loadScene(xml, d, options);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (!simulation) return nullptr;
  simulation->run();
  simulation->writeOutputs(out);
  return simulation;
}

TEST(GridRebuildTest, RebuiltGridsChangeTheCostNotTheAnswers) {
  test::TempDir withRebuild, without;
  auto rebuilt = runInto(wavingCube(true), withRebuild.path());
  auto rest = runInto(wavingCube(false), without.path());
  ASSERT_TRUE(rebuilt && rest);
  EXPECT_GT(test::componentCounter(*rest, "TetraBrain", "contact_frames"), 20);
  EXPECT_EQ(test::readFile(withRebuild / "trace.csv"), test::readFile(without / "trace.csv"));
  const double rebuilds = test::componentCounter(*rebuilt, "TetGridRebuild", "rebuilds");
  EXPECT_GT(rebuilds, 3);
  EXPECT_GT(test::componentCounter(*rebuilt, "TetraBrain", "adopted_grids"), 3);
  EXPECT_LE(test::componentCounter(*rebuilt, "TetraBrain", "adopted_grids"), rebuilds);
  // Without: many frames beyond the margin; with: a handful (between a drift and its rebuild).
  const double beyondRest = test::componentCounter(*rest, "TetraBrain", "frames_beyond_margin");
  const double beyondRebuilt = test::componentCounter(*rebuilt, "TetraBrain", "frames_beyond_margin");
  EXPECT_GT(beyondRest, 200);
  EXPECT_LT(beyondRebuilt, 0.05 * beyondRest);
}

TEST(GridRebuildTest, ItNeedsADeformationBeforeIt) {
  std::string xml = wavingCube(true);
  // The rebuild placed before the deformation: nothing deforms the brain yet when it starts.
  const std::string rebuild = R"(<TetGridRebuild name="grids" mesh="@brain" rate="100"/>)";
  xml.erase(xml.find(rebuild), rebuild.size());
  xml.insert(xml.find("<ScriptedDeformation"), rebuild + "\n    ");
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(xml, d));
  EXPECT_NE(test::messages(d).find("place it after the deformation component"), std::string::npos) << test::messages(d);
}

TEST(GridRebuildTest, OnAnotherBackEndTheSameSceneRunsAndTheRebuildIsIdle) {
  // A study varies the brain's back-end on one scene: the rebuild of the
  // native grids has nothing to do on a mesh back-end, and says so.
#ifndef TREPHINE_HAS_MESH_BACKENDS
  GTEST_SKIP() << "the bullet plugin is not built";
#endif
  // Bullet alone stands for the mesh back-ends here: Embree's worker threads
  // in this process trip LeakSanitizer's tracer under the sanitizer build,
  // and the idle path is the same for any back-end but the native one.
  for (const char* backend : {"bullet"}) {
    std::string xml = wavingCube(true);
    xml.insert(xml.find("<RequiredPlugin name=\"haptics\"/>"),
               std::string("<RequiredPlugin name=\"") + backend + "\"/>\n  ");
    xml.insert(xml.find("file=\"phantom:cube?cells=8\""), std::string("backend=\"") + backend + "\" ");
    test::TempDir with, without;
    Diagnostics d;
    SimulationOptions options;
    options.duration = 1.0;
    auto simulation = test::loadScene(xml, d, options);
    ASSERT_TRUE(simulation) << backend << ": " << test::messages(d);
    EXPECT_EQ(d.errorCount(), 0);
    EXPECT_NE(test::messages(d).find("uses another back-end, which refits or rebuilds its own tree as the mesh "
                                     "deforms, so this component does nothing"),
              std::string::npos)
        << test::messages(d);
    simulation->run();
    simulation->writeOutputs(with.path());
    EXPECT_TRUE(simulation->complete());
    EXPECT_EQ(test::componentCounter(*simulation, "TetGridRebuild", "idle"), 1.0);
    EXPECT_EQ(test::componentCounter(*simulation, "TetGridRebuild", "rebuilds"), 0.0);
    EXPECT_GT(test::componentCounter(*simulation, "TetraBrain", "contact_frames"), 20) << backend;
    // And it changes nothing: the same scene without it gives the same trace.
    std::string bare = xml;
    const std::string rebuild = R"(<TetGridRebuild name="grids" mesh="@brain" rate="100"/>)";
    bare.erase(bare.find(rebuild), rebuild.size());
    auto alone = runInto(bare, without.path());
    ASSERT_TRUE(alone);
    EXPECT_EQ(test::readFile(with / "trace.csv"), test::readFile(without / "trace.csv")) << backend;
  }
}

}  // namespace
}  // namespace trephine
