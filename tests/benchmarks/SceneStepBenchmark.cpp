// The plane_touch example scene stepped through Simulation in virtual time:
// the cost of one 1 kHz haptic group step (scripted device + spring force
// against an analytic plane), with the 60 Hz recorder running alongside.
#include <benchmark/benchmark.h>

#include <iostream>

#include "framework/runtime/Simulation.h"

namespace trephine::bench {
namespace {

constexpr double kHapticRateHz = 1000.0;
constexpr double kSimulatedSeconds = 10.0;  // per iteration: 10 000 haptic steps

void BM_PlaneTouchHapticStep(benchmark::State& state) {
  SimulationOptions options;
  options.duration = kSimulatedSeconds;
  const auto scene = std::filesystem::path(TREPHINE_SOURCE_DIR) / "scenes/examples/plane_touch.xml";
  uint64_t steps = 0;
  TimingHistogram stepTimes;  // ns, over every iteration
  for (auto _ : state) {
    state.PauseTiming();  // loading, plugin look-up and buffer allocation are not stepping
    Diagnostics diagnostics;
    auto simulation = Simulation::fromFile(scene, options, diagnostics);
    if (!simulation) {
      diagnostics.print(std::cerr);
      state.SkipWithError("plane_touch.xml did not load");
      break;
    }
    state.ResumeTiming();
    simulation->run();
    state.PauseTiming();
    const RateGroup* haptic = simulation->scheduler().group(kHapticRateHz);
    if (!simulation->complete() || !haptic) {
      state.SkipWithError("the run did not complete");
      break;
    }
    steps += haptic->calls;
    stepTimes.merge(haptic->stepHistogram);
    simulation.reset();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(static_cast<int64_t>(steps));
  const TimingSummary summary = stepTimes.summary();  // µs
  state.counters["step_p50_us"] = summary.p50;
  state.counters["step_p99_us"] = summary.p99;
  state.counters["step_max_us"] = summary.max;
  state.counters["step_mean_us"] = summary.mean;
}
BENCHMARK(BM_PlaneTouchHapticStep)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace trephine::bench

BENCHMARK_MAIN();
