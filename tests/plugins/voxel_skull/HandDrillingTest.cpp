// Closed loop while drilling: scenes/bench/hand_drill.xml, a simulated hand
// pressing a burr over the skull phantom for a minute with the pedal drilling
// half the time. Settings the load-time check calls passive stay passive (the
// observer's energy never below zero, no 100 ms window giving back more than
// the spring can hold); one it calls active gives energy back.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

std::unique_ptr<Simulation> runHandDrill(const std::vector<std::string>& overrides) {
  SimulationOptions options;
  options.overrides = overrides;
  Diagnostics d;
  auto simulation =
      Simulation::fromFile(std::filesystem::path(TREPHINE_SOURCE_DIR) / "scenes/bench/hand_drill.xml", options, d);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (simulation) simulation->run();
  return simulation;
}

TEST(HandDrillingTest, PassiveSettingsStayPassiveForAMinuteOfTouchingAndDrilling) {
  for (const char* k : {"0.5", "3"}) {
    auto simulation = runHandDrill({std::string("/tool/force.stiffness=") + k});
    ASSERT_TRUE(simulation);
    const HapticStats s = simulation->hapticLog().stats();
    const double stiffness = std::stod(k);
    EXPECT_GT(s.frames, 60000u);
    EXPECT_GT(test::componentCounter(*simulation, "VoxelSkull", "removed_bone_mm3"), 10.0) << k << ": it drilled";
    EXPECT_GE(s.minEnergyIn_mJ, -1e-6) << k << " N/mm: the contact never gave the hand energy";
    // A spring of stiffness k holding |F| stores F^2 / 2k (N mm = mJ); held over
    // each frame while the device moves up to dx a frame, a release from F gives
    // back at most F dx / 2 more (the sum of k (d - m dx) dx over the release).
    // No window gives back more.
    const HapticFrameLog& log = simulation->hapticLog();
    double largestDeviceStep = 0;  // mm per frame
    for (size_t i = 1; i < log.size(); ++i)
      largestDeviceStep = std::max(largestDeviceStep, (log[i].device - log[i - 1].device).norm());
    const double springHolds = s.forceMax * s.forceMax / (2 * stiffness) + s.forceMax * largestDeviceStep / 2;
    EXPECT_LT(s.maxGeneratedPer100ms_mJ, springHolds) << k;
    // No chatter: a proxy flipping between two places every frame shows as a
    // p99 of the force step beyond the device's motion far above the 0.02 to
    // 0.03 N of a steady walk.
    EXPECT_LT(s.unexplainedStepP99, 0.05) << k;
    EXPECT_EQ(s.nanFrames, 0u);
    EXPECT_EQ(s.proxyInsideFrames, 0u) << k;
    EXPECT_EQ(s.forceReversals, 0u) << k;
  }
}

TEST(HandDrillingTest, ASettingTheCheckCallsActiveGivesEnergyBack) {
  auto simulation = runHandDrill({"/tool/force.stiffness=20", "/tool/force.damping=0"});
  ASSERT_TRUE(simulation);
  const HapticStats s = simulation->hapticLog().stats();
  EXPECT_LT(s.minEnergyIn_mJ, -0.5) << "the rendering generated energy";
}

}  // namespace
}  // namespace trephine
