// The simulated hand runs in the haptic loop: closing the loop through it must
// not allocate (the allocations of a run do not grow with its frames).
#include <gtest/gtest.h>

#include "tests/support/AllocationCounter.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

size_t allocationsDuringRun(double durationS) {
  SimulationOptions options;
  options.duration = durationS;
  auto simulation = test::loadSceneFile("scenes/examples/hand_touch.xml", options);
  if (!simulation) return 0;
  test::startCountingAllocations();
  simulation->run();
  const size_t allocations = test::stopCountingAllocations();
  EXPECT_TRUE(simulation->complete());
  EXPECT_GT(simulation->hapticLog().stats().contactFrames, 0u) << "the hand reached the bone";
  return allocations;
}

TEST(HandNoAllocationTest, PressingWithTheHandAllocatesNothingPerFrame) {
  const size_t shortRun = allocationsDuringRun(1.5);  // approach and first contact
  const size_t longRun = allocationsDuringRun(4.8);   // press, slide and lift off
  EXPECT_EQ(longRun, shortRun) << "allocations grow with frames: the loop allocates";
  EXPECT_LE(shortRun, 4u) << "only the run's own set-up may allocate";
}

}  // namespace
}  // namespace trephine
