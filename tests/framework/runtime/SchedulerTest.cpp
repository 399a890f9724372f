// Virtual-time scheduling: call counts, due order, determinism.
#include <gtest/gtest.h>

#include "framework/core/Registry.h"
#include "framework/runtime/Scheduler.h"

namespace trephine {
namespace {

// Records (time, rate) of each call into a shared log.
struct CallLog {
  std::vector<std::pair<double, double>> calls;
};

class CountingComponent final : public Component {
 public:
  CountingComponent(double rate, CallLog* log) : m_log(log) { d_rate.setValue(rate); }
  void tick(const TickContext& context) override { m_log->calls.emplace_back(context.t, rateHz()); }

 private:
  RateField d_rate{this, 1.0};
  CallLog* m_log;
};

TEST(SchedulerTest, CallsEachRateExactlyItsRateTimesPerSimulatedSecond) {
  CallLog log;
  CountingComponent haptic(1000, &log), display(60, &log), odd(3030, &log);
  RunPlan plan;
  plan.duration = 1.0;
  Scheduler scheduler({&haptic, &display, &odd}, plan, nullptr);
  scheduler.run(std::atomic<bool>{false});

  ASSERT_TRUE(scheduler.completed());
  EXPECT_EQ(scheduler.group(1000)->calls, 1000u);
  EXPECT_EQ(scheduler.group(60)->calls, 60u);
  EXPECT_EQ(scheduler.group(3030)->calls, 3030u);
  EXPECT_EQ(log.calls.size(), 1000u + 60u + 3030u);
  EXPECT_DOUBLE_EQ(scheduler.simulatedTime(), 1.0);
}

TEST(SchedulerTest, RunsCallsInDueOrderHighestRateFirstOnTies) {
  CallLog log;
  CountingComponent slow(60, &log), fast(1000, &log), odd(3030, &log);
  RunPlan plan;
  plan.duration = 1.0;
  Scheduler scheduler({&slow, &fast, &odd}, plan, nullptr);
  scheduler.run(std::atomic<bool>{false});

  for (size_t i = 1; i < log.calls.size(); ++i) {
    const auto& [t0, r0] = log.calls[i - 1];
    const auto& [t1, r1] = log.calls[i];
    ASSERT_LE(t0, t1) << "call " << i << " runs before an earlier one";
    if (t0 == t1) {
      EXPECT_GT(r0, r1) << "at equal times the higher rate runs first";
    }
  }
  // Every call of a group is at k / rate.
  std::map<double, int> seen;
  for (const auto& [t, rate] : log.calls) {
    EXPECT_DOUBLE_EQ(t, seen[rate] / rate);
    ++seen[rate];
  }
}

TEST(SchedulerTest, PassiveComponentsFormNoGroup) {
  CallLog log;
  CountingComponent haptic(1000, &log);
  Component passive;
  RunPlan plan;
  plan.duration = 0.01;
  Scheduler scheduler({&haptic, &passive}, plan, nullptr);
  EXPECT_EQ(scheduler.groups().size(), 1u);
}

TEST(SchedulerTest, StopFlagEndsTheRunEarly) {
  CallLog log;
  CountingComponent haptic(1000, &log);
  RunPlan plan;
  plan.duration = 1.0;
  Scheduler scheduler({&haptic}, plan, nullptr);
  std::atomic<bool> stop{true};
  scheduler.run(stop);
  EXPECT_FALSE(scheduler.completed());
  EXPECT_EQ(scheduler.group(1000)->calls, 0u);
}

}  // namespace
}  // namespace trephine
