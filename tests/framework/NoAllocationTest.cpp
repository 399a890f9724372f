// The haptic loop must not allocate: count heap allocations made while a
// scene runs and check they do not grow with the number of frames.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "tests/support/TestSupport.h"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<size_t> g_allocations{0};
}  // namespace

// Replacements of the global allocation functions for this test program only.
void* operator new(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
// These replacements pair with the malloc in operator new above; GCC cannot see
// that and warns about free() on memory from new.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace trephine {
namespace {

size_t allocationsDuringRun(const char* scene, double durationS) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = durationS;
  auto simulation = Simulation::fromFile(test::sourceDir() / scene, options, d);
  EXPECT_TRUE(simulation) << test::messages(d);
  if (!simulation) return 0;
  g_allocations = 0;
  g_counting = true;
  simulation->run();
  g_counting = false;
  EXPECT_TRUE(simulation->complete());
  return g_allocations.load();
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
