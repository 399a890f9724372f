// Real-time pacing of a 1 kHz group: one trivial component run against the
// wall clock. Reports how late the group thread wakes after each deadline
// (p50, p99, max in µs), the achieved calls per second, deadline misses and
// whether SCHED_FIFO was granted. One iteration; the figures are counters.
//
// TREPHINE_BENCH_REALTIME_S sets the run length (s, default 2); the smoke
// test uses 0.3.
#include <benchmark/benchmark.h>

#include <atomic>
#include <cstdlib>
#include <string>

#include "framework/runtime/Scheduler.h"
#include "tests/benchmarks/TrivialComponent.h"

namespace trephine::bench {
namespace {

constexpr double kRateHz = 1000.0;

double runSeconds() {
  const char* text = std::getenv("TREPHINE_BENCH_REALTIME_S");
  const double seconds = text ? std::atof(text) : 0.0;
  return seconds > 0 ? seconds : 2.0;
}

void BM_RealtimeJitter1kHz(benchmark::State& state) {
  TrivialComponent component(kRateHz);
  RunPlan plan;
  plan.duration = runSeconds();
  plan.realtime = true;
  const std::atomic<bool> stop{false};
  for (auto _ : state) {
    Scheduler scheduler({&component}, plan, nullptr);
    scheduler.run(stop);
    const RateGroup& group = scheduler.groups().front();
    if (!scheduler.completed()) state.SkipWithError("the run did not complete");
    state.SetIterationTime(group.wallSeconds);
    const TimingSummary late = group.wakeLateness.summary();  // µs
    state.counters["wake_p50_us"] = late.p50;
    state.counters["wake_p99_us"] = late.p99;
    state.counters["wake_max_us"] = late.max;
    state.counters["calls_per_s"] = group.callsPerSecond();
    state.counters["deadline_misses"] = static_cast<double>(group.deadlineMisses);
    state.counters["skipped_ticks"] = static_cast<double>(group.skippedTicks);
    state.counters["sched_fifo"] = group.realtimePriority ? 1 : 0;
  }
}
BENCHMARK(BM_RealtimeJitter1kHz)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace trephine::bench

BENCHMARK_MAIN();
