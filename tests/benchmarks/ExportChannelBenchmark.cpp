// The haptic thread's own share of a VtkExporter (and of the live stream,
// which reads the same channels): each haptic frame, ForceFeedback publishes
// its force sample and TetraBrain the tool's forces on the brain's nodes, and
// a VtkExporter is one more reader of both channels: one more copy into a
// triple buffer's slot each. Everything else the exporter does (reading the
// slots, building and writing files, streaming) runs in its own group, off
// the haptic thread.
//
// One benchmark run measures the publish with and without the exporter's
// readers, interleaved in blocks of frames so that both see the same machine,
// while a second thread fetches the exporter's slots at 30 Hz as its group
// does. The other readers of a scene (the Recorder's of the sample, the
// deformer's of the node forces) are there in both arms. Counters (ns per
// frame): p50, p99 and max of the publish with and without the exporter, and
// the p99 difference.
//
// Argument: node forces in a frame, the nodes the tool's force is shared
// among (TetraBrain's counter largest_node_force_count: 11 on
// scenes/integrated.xml, 195 on integrated_atlas.xml).
#include <benchmark/benchmark.h>

#include <atomic>
#include <chrono>
#include <optional>
#include <thread>

#include "framework/channels/Channel.h"
#include "framework/core/SampleSource.h"
#include "framework/runtime/TimingHistogram.h"
#include "framework/data/MeshDeformation.h"

namespace trephine::bench {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kFramesPerBlock = 1000;  // 1 s of haptics at 1 kHz

// The two channels a haptic frame publishes to, with the readers of a
// scene (the Recorder's, the deformer's) and, in one arm, the exporter's.
struct Channels {
  Channel<Sample> samples;
  Channel<NodeForces> nodeForces;
  ChannelReader<Sample> recorder;
  ChannelReader<NodeForces> deformer;
  std::optional<ChannelReader<Sample>> exporterSamples;
  std::optional<ChannelReader<NodeForces>> exporterForces;

  Channels(size_t nodes, bool withExporter) : recorder(samples.addReader()), deformer(nodeForces.addReader()) {
    NodeForces prototype;
    prototype.forces.resize(nodes);
    nodeForces.reserve(prototype);
    if (withExporter) {
      exporterSamples.emplace(samples.addReader());
      exporterForces.emplace(nodeForces.addReader());
    }
  }
};

void BM_HapticPublishForExporter(benchmark::State& state) {
  const size_t nodes = size_t(state.range(0));
  Channels without(nodes, false), with(nodes, true);
  Sample sample;
  NodeForces forces;
  forces.forces.resize(nodes);
  for (size_t n = 0; n < nodes; ++n) forces.forces[n] = {int32_t(n * 7), Vec3(0.01 * double(n), -0.02, 0.3)};

  // The exporter's group: fetches its slots at 30 Hz and touches what it
  // read, as writing a frame would.
  std::atomic<bool> stop{false};
  std::atomic<double> sink{0};
  std::thread exporter([&] {
    while (!stop.load(std::memory_order_relaxed)) {
      double sum = 0;
      if (with.exporterSamples->fetch()) sum += with.exporterSamples->read().values[0];
      if (with.exporterForces->fetch())
        for (const NodeForce& f : with.exporterForces->read().forces) sum += f.force.x();
      sink.store(sum, std::memory_order_relaxed);
      std::this_thread::sleep_for(std::chrono::microseconds(33'333));
    }
  });

  TimingHistogram withTimes, withoutTimes;  // ns per frame
  uint64_t frame = 0;
  for (auto _ : state) {
    for (Channels* channels : {&without, &with}) {
      TimingHistogram& times = channels == &with ? withTimes : withoutTimes;
      for (int i = 0; i < kFramesPerBlock; ++i, ++frame) {
        sample.t = forces.t = double(frame) * 1e-3;
        sample.values[0] = double(frame % 97);
        if (nodes > 0) forces.forces[frame % nodes].force.y() = double(frame % 13);
        const auto start = Clock::now();
        channels->samples.publish(sample);
        channels->nodeForces.publish(forces);
        times.record(uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start).count()));
        // The other readers fetch every frame (the Recorder at 1 kHz).
        channels->recorder.fetch();
        channels->deformer.fetch();
      }
    }
  }
  stop = true;
  exporter.join();
  benchmark::DoNotOptimize(sink.load());
  state.SetItemsProcessed(int64_t(withTimes.count()));
  state.counters["without_p50_ns"] = withoutTimes.quantileNs(0.5);
  state.counters["without_p99_ns"] = withoutTimes.quantileNs(0.99);
  state.counters["without_max_ns"] = double(withoutTimes.maxNs());
  state.counters["with_p50_ns"] = withTimes.quantileNs(0.5);
  state.counters["with_p99_ns"] = withTimes.quantileNs(0.99);
  state.counters["with_max_ns"] = double(withTimes.maxNs());
  state.counters["p99_added_ns"] = withTimes.quantileNs(0.99) - withoutTimes.quantileNs(0.99);
}
BENCHMARK(BM_HapticPublishForExporter)->Arg(0)->Arg(16)->Arg(64)->Arg(256)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace trephine::bench

BENCHMARK_MAIN();
