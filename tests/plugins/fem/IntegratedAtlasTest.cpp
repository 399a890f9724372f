// scenes/integrated_atlas.xml, the integrated procedure on the atlas brain
// of ../shared/data, cut short. Seconds of arithmetic on 145,391 elements
// (minutes under AddressSanitizer), so the sanitizer presets leave it out
// (label realdata); skipped when the data is absent.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "framework/core/Diagnostics.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

// scenes/integrated_atlas.xml, cut short: the change at 50 ms and the probe
// straight down onto the brain (the skull is no longer its target), pressing
// for about 0.1 s (each millisecond of the 145,391-element FEM costs about
// 60 ms here).
TEST(IntegratedAtlasTest, OnTheAtlasBrainTheProbeDeformsItWithForceAndNothingRunsBeforeIt) {
  const std::filesystem::path scene = test::sourceDir() / "scenes/integrated_atlas.xml";
  if (!std::filesystem::exists(test::sourceDir() / "../shared/data/brain_tetmesh_mmc_head_atlas"))
    GTEST_SKIP() << "needs ../shared/data/brain_tetmesh_mmc_head_atlas, which is absent";
  Diagnostics d;
  SimulationOptions options;
  options.duration = 0.3;
  // The brain's surface is at z = 50.0 under (25, 0): the probe's centre touches at 52.5.
  options.overrides = {"/tool/change.time=0.05", "/tool/device.buttonTimes=",
                       "/tool/device.waypoints=0 25 0 56  0.15 25 0 53  0.3 25 0 51"};
  auto simulation = Simulation::fromFile(scene, options, d);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  size_t changes = 0;
  for (size_t i = 0; i < simulation->events().size(); ++i)
    changes += std::string("tool_change") == simulation->events()[i].kind;
  EXPECT_EQ(changes, 1u);
  EXPECT_GT(test::componentCounter(*simulation, "TetraBrain", "contact_frames"), 50);
  EXPECT_GT(test::componentCounter(*simulation, "TLEDForceField", "force_updates"), 50);
  // Nothing touched the brain for its first 0.2 s: the FEM rested, computing nothing.
  EXPECT_GT(test::componentCounter(*simulation, "TLEDForceField", "resting_steps"), 150 * 20);
  const double moved = test::componentCounter(*simulation, "TLEDForceField", "largest_displacement_mm");
  EXPECT_GT(moved, 0.05);
  EXPECT_LT(moved, 5.0);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "non_finite_ticks"), 0);
  EXPECT_EQ(test::componentCounter(*simulation, "TLEDForceField", "inverted_element_steps"), 0);
  EXPECT_EQ(simulation->hapticLog().stats().nanFrames, 0u);
  double largest = 0;
  const HapticFrameLog& log = simulation->hapticLog();
  for (size_t i = 0; i < log.size(); ++i) largest = std::max(largest, log[i].force.norm());
  EXPECT_GT(largest, 0.1);  // 1 to 2 mm into a 0.3 N/mm spring
  EXPECT_LT(largest, 1.0);
}

}  // namespace
}  // namespace trephine
