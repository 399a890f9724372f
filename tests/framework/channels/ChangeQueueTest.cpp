// ChangeQueue: every value, in order, across two threads (run under
// ThreadSanitizer in CI); a full ring drops and counts instead of blocking.
#include <gtest/gtest.h>

#include <thread>

#include "framework/channels/ChangeQueue.h"

namespace trephine {
namespace {

TEST(ChangeQueueTest, AReaderSeesEveryValueInOrderAcrossThreads) {
  ChangeQueue<uint64_t> queue(1024);
  constexpr uint64_t kValues = 2'000'000;
  std::thread writer([&] {
    for (uint64_t v = 0; v < kValues;)
      if (queue.push(v)) ++v;  // a full ring: try again (the test's writer may wait; a haptic loop would not)
  });
  uint64_t expected = 0;
  bool inOrder = true;
  while (expected < kValues)
    queue.drain([&](uint64_t v) {
      inOrder = inOrder && v == expected;
      ++expected;
    });
  writer.join();
  EXPECT_TRUE(inOrder);
  EXPECT_EQ(expected, kValues);
}

TEST(ChangeQueueTest, AFullRingDropsAndCountsWhatItCannotHold) {
  ChangeQueue<int> queue(3);  // rounded up to 4
  EXPECT_EQ(queue.capacity(), 4u);
  for (int v = 0; v < 6; ++v) queue.push(v);
  EXPECT_EQ(queue.dropped(), 2u);
  std::vector<int> seen;
  EXPECT_EQ(queue.drain([&](int v) { seen.push_back(v); }), 4u);
  EXPECT_EQ(seen, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(queue.drain([&](int) { ADD_FAILURE() << "nothing new"; }), 0u);
  EXPECT_TRUE(queue.push(7));
  seen.clear();
  queue.drain([&](int v) { seen.push_back(v); });
  EXPECT_EQ(seen, (std::vector<int>{7}));
}

}  // namespace
}  // namespace trephine
