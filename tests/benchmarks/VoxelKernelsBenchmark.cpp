// The inner kernels of rigid voxel collision on the Skull5-size phantom
// (425 x 403 x 283 voxels of 0.5 mm): the per-point voxel test of a 466-point
// shell (baseline SSE2 and AVX2 versions, ns per point), and the line sweep of
// the leading point over typical per-frame moves.
//   build/bin/voxel_kernels_benchmark [--benchmark_repetitions=10]
// TREPHINE_BENCH_VOXEL (mm, default 0.5) sets the phantom's voxel size.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <random>

#include "plugins/haptics/ShellSampling.h"
#include "plugins/voxel_skull/Phantoms.h"
#include "plugins/voxel_skull/ShellPointTest.h"
#include "plugins/voxel_skull/VoxelTraversal.h"

namespace trephine::bench {
namespace {

using namespace trephine::voxel;

constexpr double kRadius = 2.5;  // mm
constexpr int kShellPoints = 466;

DensityVolume& phantom() {
  static DensityVolume volume = [] {
    const char* size = std::getenv("TREPHINE_BENCH_VOXEL");
    return makeSkullPhantom(size ? std::atof(size) : 0.5);
  }();
  return volume;
}

// Burr placements on the top of the skull, touching the bone (centres 2.2 mm above the top surface).
std::vector<Pose> placements(const SolidGrid& grid) {
  std::vector<Pose> out;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> offset(-10, 10);
  while (out.size() < 256) {
    Vec3 p(offset(random), offset(random), 80);
    while (p.z() > -80 && !grid.solidAt(p)) p.z() -= 0.05;
    p.z() += kRadius - 0.3;
    Pose pose;
    pose.position = p;
    out.push_back(pose);
  }
  return out;
}

template <ShellPointTestFunction test>
void BM_ShellPointTest(benchmark::State& state) {
  const SolidGrid grid = SolidGrid::of(phantom(), 400.0);
  std::vector<ShellPoint> shell;
  for (const Vec3& d : haptics::evenDirections(kShellPoints)) shell.push_back({kRadius * d, -d});
  ShellArrays arrays;
  arrays.assign(shell);
  std::vector<int64_t> voxels(shell.size());
  std::vector<uint8_t> solid(shell.size());
  const std::vector<Pose> poses = placements(grid);
  size_t k = 0, touching = 0;
  for (auto _ : state) {
    test(grid, arrays, poses[k++ & 255], {voxels.data(), solid.data()});
    touching += solid[0];
    benchmark::DoNotOptimize(solid.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_point"] = benchmark::Counter(double(state.iterations()) * kShellPoints,
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ShellPointTest<testShellPointsBaseline>)->Name("ShellPointTest/sse2");
#ifdef TREPHINE_HAS_AVX2_PATH
BENCHMARK(BM_ShellPointTest<testShellPointsAvx2>)->Name("ShellPointTest/avx2");
#endif

// The leading point of the burr swept over a move of state.range(0) um per frame.
void BM_LineSweep(benchmark::State& state) {
  const SolidGrid grid = SolidGrid::of(phantom(), 400.0);
  const std::vector<Pose> poses = placements(grid);
  const double move = state.range(0) * 1e-3;  // mm
  size_t k = 0, hits = 0;
  for (auto _ : state) {
    const Vec3 from = poses[k++ & 255].position;
    const Vec3 to = from + Vec3(0.6, 0.3, -0.74).normalized() * move;
    const Vec3 lead = (to - from).normalized() * kRadius;
    hits += firstSolidOnSegment(grid, from + lead, to + lead, false).hit;
  }
  benchmark::DoNotOptimize(hits);
}
BENCHMARK(BM_LineSweep)->Arg(20)->Arg(200)->Arg(5000);

}  // namespace
}  // namespace trephine::bench

BENCHMARK_MAIN();
