// EventLog: events logged from several threads while another reads them as
// they come (readSince, as ToolChange does): every event is read once, whole,
// in each writer's order. Run under ThreadSanitizer in CI (label "threaded"):
// a read of an entry still being written would be reported.
#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "framework/logs/EventLog.h"

namespace trephine {
namespace {

TEST(EventLogTest, AReaderSeesEveryEventOnceWholeAndInEachWritersOrder) {
  constexpr int kWriters = 2, kEach = 20000;
  EventLog log(kWriters * kEach);
  const char* kinds[kWriters] = {"first", "second"};
  std::vector<std::thread> writers;
  for (int w = 0; w < kWriters; ++w)
    writers.emplace_back([&, w] {
      for (int k = 0; k < kEach; ++k) log.log(0.001 * k, kinds[w], "test", nullptr, double(k));
    });
  std::vector<int> next(kWriters, 0);  // per writer, the value expected next
  size_t read = 0, position = 0;
  bool ordered = true;
  while (read < size_t(kWriters * kEach)) {
    position = log.readSince(position, [&](const Event& e) {
      const int w = e.kind == kinds[0] ? 0 : 1;
      ordered = ordered && e.value == double(next[w]) && e.t == 0.001 * next[w];
      ++next[w];
      ++read;
    });
  }
  for (std::thread& t : writers) t.join();
  EXPECT_TRUE(ordered);
  EXPECT_EQ(next[0], kEach);
  EXPECT_EQ(next[1], kEach);
  EXPECT_EQ(log.readSince(position, [](const Event&) { ADD_FAILURE() << "read twice"; }), position);
}

TEST(EventLogTest, EventsPastTheCapacityAreCountedNotRead) {
  EventLog log(2);
  for (int k = 0; k < 5; ++k) log.log(0, "kind", "", nullptr, k);
  size_t seen = 0;
  EXPECT_EQ(log.readSince(0, [&](const Event&) { ++seen; }), 2u);
  EXPECT_EQ(seen, 2u);
  EXPECT_EQ(log.dropped(), 3u);
}

}  // namespace
}  // namespace trephine
