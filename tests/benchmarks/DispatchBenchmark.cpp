// Virtual-time dispatch cost: one Scheduler over N trivial components of one
// 1 kHz group, run for a long planned duration. The time per component call
// includes the scheduler's own per-call work (one clock read, a histogram
// record, the per-call duration store); the target is under 0.2 µs.
#include <benchmark/benchmark.h>

#include <atomic>
#include <memory>
#include <vector>

#include "framework/runtime/Scheduler.h"
#include "tests/benchmarks/TrivialComponent.h"

namespace trephine::bench {
namespace {

constexpr double kRateHz = 1000.0;
constexpr double kCallsPerRun = 1e6;  // component calls per benchmark iteration

void BM_VirtualDispatch(benchmark::State& state) {
  const auto componentCount = static_cast<size_t>(state.range(0));
  std::vector<std::unique_ptr<TrivialComponent>> owned;
  std::vector<Component*> components;
  for (size_t i = 0; i < componentCount; ++i) {
    owned.push_back(std::make_unique<TrivialComponent>(kRateHz));
    components.push_back(owned.back().get());
  }
  RunPlan plan;
  plan.duration = kCallsPerRun / (kRateHz * static_cast<double>(componentCount));  // s of virtual time
  const std::atomic<bool> stop{false};
  uint64_t calls = 0;
  TimingHistogram callTimes;  // ns per call as the scheduler recorded them, every member and iteration
  for (auto _ : state) {
    state.PauseTiming();  // building the scheduler allocates the per-call buffers
    auto scheduler = std::make_unique<Scheduler>(components, plan, nullptr);
    state.ResumeTiming();
    scheduler->run(stop);
    state.PauseTiming();  // tallying and freeing the buffers is not dispatch either
    if (!scheduler->completed()) state.SkipWithError("the run did not complete");
    calls += scheduler->groups().front().calls * componentCount;
    for (const GroupMember& member : scheduler->groups().front().members) callTimes.merge(member.histogram);
    scheduler.reset();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(static_cast<int64_t>(calls));
  // Seconds per component call; shown with an SI prefix ("45n" = 45 ns).
  state.counters["per_call"] =
      benchmark::Counter(static_cast<double>(calls), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  // The scheduler's own view: clock read to clock read around each tick (µs -> ns).
  const TimingSummary recorded = callTimes.summary();
  state.counters["recorded_p50_ns"] = recorded.p50 * 1e3;
  state.counters["recorded_p99_ns"] = recorded.p99 * 1e3;
}
BENCHMARK(BM_VirtualDispatch)->Arg(1)->Arg(4)->Arg(16)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace trephine::bench

BENCHMARK_MAIN();
