// The coupled FEM and haptic loop judged as numbers: a run repeats byte for
// byte, and smoothing the tool's force on the nodes stops the chatter of a
// spring on a soft brain. Seconds of simulation each, so the sanitizer
// presets leave them out (label numerics); FemSceneTest runs the same path
// there.
#include <gtest/gtest.h>

#include "framework/core/Diagnostics.h"
#include "tests/plugins/fem/FemScenes.h"
#include "tests/support/TestSupport.h"

namespace trephine::fem {
namespace {

using scenes::pressScene;
using scenes::runFor;

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
