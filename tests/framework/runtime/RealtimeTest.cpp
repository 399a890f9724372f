// Real-time runs: a 1 kHz group paced by the wall clock, a 60 Hz group reading
// what the fast group publishes through a channel (data crossing threads), and
// the number of group threads a scene gets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "framework/core/ChannelHub.h"
#include "framework/runtime/Scheduler.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

// One published value. `check` is derived from the others, so a reader can
// tell a value that was written whole from one torn by a concurrent write.
struct Reading {
  uint64_t frame = 0;
  double t = 0;  // s
  double check = 0;
};
double checkOf(uint64_t frame, double t) { return static_cast<double>(frame) * 0.5 + t; }

class FastPublisher final : public Component {
 public:
  FastPublisher() { d_rate.setValue(1000.0); }
  void connect(ChannelHub& hub) { m_channel = &hub.publish<Reading>(*this, "reading"); }
  void tick(const TickContext& context) override {
    m_channel->publish({context.frame, context.t, checkOf(context.frame, context.t)});
  }

 private:
  RateField d_rate{this, 1000.0};
  Channel<Reading>* m_channel = nullptr;
};

class SlowReader final : public Component {
 public:
  SlowReader() { d_rate.setValue(60.0); }
  void connect(ChannelHub& hub, const FastPublisher& publisher) {
    m_reader.emplace(hub.subscribe<Reading>(publisher, "reading"));
  }
  void tick(const TickContext&) override {
    if (!m_reader->fetch()) return;
    const Reading& r = m_reader->read();
    ++freshReads;
    if (r.check != checkOf(r.frame, r.t)) ++tornReads;
    if (freshReads > 1 && r.frame <= lastFrame) ++outOfOrderReads;
    lastFrame = r.frame;
  }

  uint64_t freshReads = 0, tornReads = 0, outOfOrderReads = 0;
  uint64_t lastFrame = 0;  // the newest fast frame seen

 private:
  RateField d_rate{this, 60.0};
  std::optional<ChannelReader<Reading>> m_reader;
};

TEST(RealtimeTest, FastGroupKeepsItsRateWhileASlowGroupReadsItsChannel) {
  FastPublisher fast;
  SlowReader slow;
  ChannelHub hub;  // channels are wired before the group threads start
  fast.connect(hub);
  slow.connect(hub, fast);
  RunPlan plan;
  plan.duration = 2.0;  // s
  plan.realtime = true;
  Scheduler scheduler({&fast, &slow}, plan, nullptr);
  scheduler.run(std::atomic<bool>{false});
  ASSERT_TRUE(scheduler.completed());
  ASSERT_FALSE(scheduler.failure()) << *scheduler.failure();

  const RateGroup& fastGroup = *scheduler.group(1000.0);
  const RateGroup& slowGroup = *scheduler.group(60.0);
  const double callsPerSecond = fastGroup.callsPerSecond();
  const TimingSummary lateness = fastGroup.wakeLateness.summary();  // µs
  std::printf(
      "1 kHz group: %.1f calls/s over %.3f s, wake lateness p50 %.1f us p99 %.1f us max %.1f us, "
      "%llu deadline misses, %llu skipped ticks, SCHED_FIFO %s\n",
      callsPerSecond, fastGroup.wallSeconds, lateness.p50, lateness.p99, lateness.max,
      static_cast<unsigned long long>(fastGroup.deadlineMisses),
      static_cast<unsigned long long>(fastGroup.skippedTicks), fastGroup.realtimePriority ? "yes" : "no");
  std::printf("60 Hz group: %llu calls, %llu fresh reads, newest frame read %llu\n",
              static_cast<unsigned long long>(slowGroup.calls), static_cast<unsigned long long>(slow.freshReads),
              static_cast<unsigned long long>(slow.lastFrame));
  RecordProperty("calls_per_second", std::to_string(callsPerSecond));
  RecordProperty("wake_lateness_p99_us", std::to_string(lateness.p99));
  RecordProperty("deadline_misses", std::to_string(fastGroup.deadlineMisses));

  EXPECT_NEAR(callsPerSecond, 1000.0, 50.0) << "calls per wall second of the 1 kHz group";
  EXPECT_GE(slowGroup.calls, 110u) << "2 s at 60 Hz is 120 calls";

  // The slow group saw the fast group's values, whole and in order, up to near the end of the run.
  EXPECT_GT(slow.freshReads, slowGroup.calls / 2);
  EXPECT_EQ(slow.tornReads, 0u);
  EXPECT_EQ(slow.outOfOrderReads, 0u);
  EXPECT_LT(slow.lastFrame, fastGroup.plannedCalls);
  EXPECT_GT(slow.lastFrame, 1900u) << "the last 60 Hz tick (t ~ 1.98 s) reads a recent 1 kHz frame";
}

std::string planeScene(const std::string& extra) {
  return R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <AnalyticPlane name="plane"/>
  <ScriptedDevice name="device" path="drill-in" target="@plane" tipOffset="2.5" rate="1000"/>
  <SphereTool name="burr" radius="2.5" device="@device"/>
  <SpringForce name="force" tool="@burr" target="@plane" rate="1000"/>
  )" + extra +
         R"(
</Node>)";
}

TEST(RealtimeTest, SceneWithoutRecorderRunsOneGroupThread) {
  SimulationOptions options;
  options.realtime = true;
  options.duration = 0.2;  // s
  Diagnostics diagnostics;
  auto simulation = test::loadScene(planeScene(""), diagnostics, options);
  ASSERT_TRUE(simulation) << test::messages(diagnostics);
  // One rate group is one thread in real time: no recorder thread.
  ASSERT_EQ(simulation->scheduler().groups().size(), 1u);
  EXPECT_EQ(simulation->scheduler().groups().front().rateHz, 1000.0);
  simulation->run();
  EXPECT_TRUE(simulation->complete()) << simulation->incompleteReason();
  EXPECT_EQ(simulation->scheduler().groups().front().calls + simulation->scheduler().groups().front().skippedTicks,
            200u);

  // The same scene with a recorder gets a second group, hence a second thread.
  Diagnostics withRecorder;
  auto recorded =
      test::loadScene(planeScene(R"(<Recorder name="recorder" source="@force" rate="60"/>)"), withRecorder, options);
  ASSERT_TRUE(recorded) << test::messages(withRecorder);
  EXPECT_EQ(recorded->scheduler().groups().size(), 2u);
}

}  // namespace
}  // namespace trephine
