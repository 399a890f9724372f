// The haptic loop must not allocate: count heap allocations made while a
// scene runs and check they do not grow with the number of frames.
#include <gtest/gtest.h>

#include "tests/support/AllocationCounter.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

TEST(NoAllocationTest, TheCounterSeesAnAllocation) {
  // Without this, a counter that never counts would pass every test below.
  test::startCountingAllocations();
  auto* volatile value = new int(7);
  const size_t counted = test::stopCountingAllocations();
  delete value;
  EXPECT_EQ(counted, 1u);
}

size_t allocationsDuringRun(const char* scene, double durationS) {
  SimulationOptions options;
  options.duration = durationS;
  auto simulation = test::loadSceneFile(scene, options);
  if (!simulation) return 0;
  test::startCountingAllocations();
  simulation->run();
  const size_t allocations = test::stopCountingAllocations();
  EXPECT_TRUE(simulation->complete());
  return allocations;
}

TEST(NoAllocationTest, RunningMoreFramesAllocatesNothingMore) {
  const size_t shortRun = allocationsDuringRun("scenes/examples/plane_touch.xml", 0.2);  // 200 haptic frames
  const size_t longRun = allocationsDuringRun("scenes/examples/plane_touch.xml", 2.0);   // 2000 haptic frames
  EXPECT_EQ(longRun, shortRun) << "allocations grow with frames: the loop allocates";
  EXPECT_LE(shortRun, 4u) << "only the run's own set-up may allocate";
}

TEST(NoAllocationTest, TouchingAndDrillingTheSkullAllocatesNothingPerFrame) {
  // craniotomy.xml: approach, touch, drill with the cylinder sweep, retract.
  const size_t shortRun = allocationsDuringRun("scenes/craniotomy.xml", 1.0);
  const size_t longRun = allocationsDuringRun("scenes/craniotomy.xml", 5.0);
  EXPECT_EQ(longRun, shortRun) << "allocations grow with frames: the loop allocates";
  EXPECT_LE(shortRun, 4u) << "only the run's own set-up may allocate";
}

TEST(NoAllocationTest, TouchingABrainWhoseEveryNodeMovesAllocatesNothingPerFrame) {
  // tet_wave_circle.xml: the deformation publishes every node every frame, the
  // brain reads them, the tool circles on the surface (node forces unread).
  const size_t shortRun = allocationsDuringRun("scenes/bench/tet_wave_circle.xml", 0.5);
  const size_t longRun = allocationsDuringRun("scenes/bench/tet_wave_circle.xml", 2.5);
  EXPECT_EQ(longRun, shortRun) << "allocations grow with frames: the loop allocates";
  EXPECT_LE(shortRun, 4u) << "only the run's own set-up may allocate";
}

}  // namespace
}  // namespace trephine
