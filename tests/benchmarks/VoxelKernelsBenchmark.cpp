// The inner kernels of rigid voxel collision on the Skull5-size phantom
// (425 x 403 x 283 voxels of 0.5 mm): the per-point test of a 466-point shell
// against the voxel and the smooth surface (baseline SSE2 and AVX2 versions,
// ns per point; on the smooth surface also the one-point-at-a-time reference
// and the fast test without occupancy cells), the line sweep of the
// leading point over per-frame moves, and one frame of force-driven drilling.
//   build/bin/voxel_kernels_benchmark [--benchmark_repetitions=10]
// TREPHINE_BENCH_VOXEL (mm, default 0.5) sets the phantom's voxel size.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <random>

#include "framework/runtime/TimingHistogram.h"
#include "framework/geometry/ShellSampling.h"
#include "plugins/voxel_skull/FootprintCut.h"
#include "framework/data/IsoSurface.h"
#include "plugins/voxel_skull/Phantoms.h"
#include "plugins/voxel_skull/ShellPointClassifier.h"
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

constexpr size_t kPlacements = 2048;  // a power of two

// Burr placements along a 5 mm circle on the top of the skull, 15 um apart (15
// mm/s at 1 kHz), each pressing 0.3 mm into the bone: consecutive calls touch
// neighbouring voxels, as consecutive haptic frames do.
std::vector<Pose> placements(const SolidGrid& grid) {
  std::vector<Pose> out;
  for (size_t k = 0; k < kPlacements; ++k) {
    const double angle = 2 * 3.14159265358979 * double(k) / kPlacements * 0.4;
    Vec3 p(5 * std::cos(angle), 5 * std::sin(angle), 80);
    while (p.z() > -80 && !grid.solidAt(p)) p.z() -= 0.01;
    p.z() += kRadius - 0.3;
    Pose pose;
    pose.position = p;
    out.push_back(pose);
  }
  return out;
}

// The smooth test as it was before the occupancy cells and gathers (one point
// at a time through SolidGrid::codeAt), compiled for AVX2 as it was: the
// reference the fast versions are compared with (testShellPointsSmoothScalar
// is the same code for the x86-64 baseline).
#ifdef TREPHINE_HAS_AVX2_PATH
__attribute__((target("avx2"))) void testShellPointsSmoothScalarAvx2(const SolidGrid& grid, const ShellArrays& shell,
                                                                     const Pose& X_WT, PointTestOutput out) {
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  for (size_t i = 0; i < shell.size(); ++i) {
    const Vec3 p = R * Vec3(shell.x[i], shell.y[i], shell.z[i]) + X_WT.position;
    out.solid[i] = grid.codeAt(p) > grid.isoCode;
    out.voxel[i] = grid.voxelOf(p);
  }
}
#endif

// cells: the smooth grid gets its occupancy cells (as VoxelSkull builds them).
template <ShellPointTestFunction test, bool smooth, bool cells = false>
void BM_ShellPointTest(benchmark::State& state) {
  SolidGrid grid = SolidGrid::of(phantom(), 400.0, smooth);
  if (cells) {
    static const std::shared_ptr<OccupancyCells> built = [&grid] {
      grid.buildOccupancy();
      return grid.occupancy;
    }();
    grid.occupancy = built;
  }
  std::vector<ShellPoint> shell;
  for (const Vec3& d : evenDirections(kShellPoints)) shell.push_back({kRadius * d, -d});
  ShellArrays arrays;
  arrays.assign(shell);
  std::vector<int64_t> voxels(shell.size());
  std::vector<uint8_t> solid(shell.size());
  const std::vector<Pose> poses = placements(grid);
  size_t k = 0, touching = 0;
  for (auto _ : state) {
    test(grid, arrays, poses[k++ & (kPlacements - 1)], {voxels.data(), solid.data()});
    touching += solid[0];
    benchmark::DoNotOptimize(solid.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_point"] = benchmark::Counter(double(state.iterations()) * kShellPoints,
                                                      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  if (smooth) {
    // Where the points of the placements fall (codeAt's cases), and with cells
    // the share that interpolates: a point inside the grid in a surface cell.
    size_t beyond = 0, onFaces = 0, interpolated = 0, bone = 0;
    const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
    for (const Pose& pose : poses) {
      for (const ShellPoint& point : shell) {
        const Vec3 p = identity * point.position + pose.position;
        const Vec3 u = (p - grid.corner).cwiseProduct(grid.inverseSpacing) - Vec3::Constant(0.5);
        bone += grid.codeAt(p) > grid.isoCode;
        if (!(u.x() > -2 && u.y() > -2 && u.z() > -2 && u.x() < grid.nx + 1 && u.y() < grid.ny + 1 &&
              u.z() < grid.nz + 1)) {
          ++beyond;
          continue;
        }
        const int64_t i = int64_t(std::floor(u.x())), j = int64_t(std::floor(u.y())), l = int64_t(std::floor(u.z()));
        const bool interior = i >= 0 && j >= 0 && l >= 0 && i + 1 < grid.nx && j + 1 < grid.ny && l + 1 < grid.nz;
        const bool surface = !grid.occupancy ||
                             grid.occupancy->state(grid.occupancy->cellIndex(i, j, l)) == OccupancyCells::kSurface;
        if (surface) ++(interior ? interpolated : onFaces);
      }
    }
    const double total = double(poses.size() * shell.size());
    state.counters["share_bone"] = double(bone) / total;
    state.counters["share_beyond_grid"] = double(beyond) / total;
    state.counters["share_interpolated"] = double(interpolated) / total;
    state.counters["share_codeAt"] = double(onFaces) / total;
  }
}
BENCHMARK(BM_ShellPointTest<testShellPointsBaseline, false>)->Name("ShellPointTest/voxels/sse2");
BENCHMARK(BM_ShellPointTest<testShellPointsSmoothScalar, true>)->Name("ShellPointTest/smooth/sse2/reference");
BENCHMARK(BM_ShellPointTest<testShellPointsSmoothBaseline, true>)->Name("ShellPointTest/smooth/sse2/no-cells");
BENCHMARK(BM_ShellPointTest<testShellPointsSmoothBaseline, true, true>)->Name("ShellPointTest/smooth/sse2");
#ifdef TREPHINE_HAS_AVX2_PATH
BENCHMARK(BM_ShellPointTest<testShellPointsAvx2, false>)->Name("ShellPointTest/voxels/avx2");
BENCHMARK(BM_ShellPointTest<testShellPointsSmoothScalarAvx2, true>)->Name("ShellPointTest/smooth/avx2/reference");
BENCHMARK(BM_ShellPointTest<testShellPointsSmoothAvx2, true>)->Name("ShellPointTest/smooth/avx2/no-cells");
BENCHMARK(BM_ShellPointTest<testShellPointsSmoothAvx2, true, true>)->Name("ShellPointTest/smooth/avx2");
#endif

// The drilling hook: OccupancyCells::lowered (SolidGrid::noteLowered) for
// bone voxels lowered below the isovalue, those within 8 mm of the top of the
// skull where the burr circles (on a copy of the cells, so the phantom's stay
// intact), ns per call.
void BM_NoteLowered(benchmark::State& state) {
  SolidGrid grid = SolidGrid::of(phantom(), 400.0, true);
  grid.buildOccupancy();
  Vec3 top(0, 0, 80);
  while (top.z() > -80 && !grid.solidAt(top)) top.z() -= 0.01;
  std::vector<int64_t> voxels;  // bone voxels near the top, in memory order
  for (int64_t v = 0; v < int64_t(grid.nx) * grid.ny * grid.nz; ++v)
    if (grid.codes[v] > grid.isoCode && (grid.centerOf(v) - top).norm() < 8.0) voxels.push_back(v);
  const OccupancyCells original = *grid.occupancy;
  size_t k = 0;
  for (auto _ : state) {
    if (k == voxels.size()) {  // every voxel done: the next round finds the cells changed already
      state.PauseTiming();
      *grid.occupancy = original;
      k = 0;
      state.ResumeTiming();
    }
    grid.noteLowered(voxels[k++], 0);
  }
  state.counters["voxels"] = double(voxels.size());
}
BENCHMARK(BM_NoteLowered);

// The leading point of the burr swept over a move of state.range(0) um per frame
// (20 um: 20 mm/s at 1 kHz), against the voxel (range(1) = 0) or smooth surface.
void BM_LineSweep(benchmark::State& state) {
  const SolidGrid grid = SolidGrid::of(phantom(), 400.0, state.range(1) != 0);
  const std::vector<Pose> poses = placements(grid);
  const double move = state.range(0) * 1e-3;  // mm
  size_t k = 0, hits = 0;
  TimingHistogram perCall;  // ns of each sweep, clock reads included (about 20 ns)
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    // From 1 mm above the contact towards the bone: the free part is traversed.
    const Vec3 from = poses[k++ & (kPlacements - 1)].position + Vec3(0, 0, 1.0);
    const Vec3 to = from + Vec3(0.6, 0.3, -0.74).normalized() * move;
    const Vec3 lead = (to - from).normalized() * kRadius;
    hits += firstSolidOnSegment(grid, from + lead, to + lead, false).hit;
    perCall.record(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
  }
  benchmark::DoNotOptimize(hits);
  const TimingSummary summary = perCall.summary();  // us
  state.counters["call_p50_us"] = summary.p50;
  state.counters["call_p99_us"] = summary.p99;
  state.counters["call_max_us"] = summary.max;
}
BENCHMARK(BM_LineSweep)->ArgsProduct({{20, 200, 5000}, {0, 1}})->ArgNames({"move_um", "smooth"});

// One frame of force-driven drilling (FootprintCut.h): the burr at the
// placements of the circle, its centre state.range(0) um deeper than where the
// benchmark's other kernels press (0.3 mm into the top of the skull; 2,000 um:
// the burr sunk in bone to its equator, the heaviest footprint), cutting 20 um
// a frame (20 mm/s, the law's cap) straight down, on a copy of the phantom's
// codes restored every 2048 frames (outside the timing); us per frame.
template <FootprintCutResult (*cut)(SolidGrid&, const FootprintCut&)>
void BM_FootprintCut(benchmark::State& state) {
  static DensityVolume volume = phantom();  // a copy: the phantom stays intact
  SolidGrid grid = SolidGrid::of(volume, 400.0, true);
  const std::vector<Pose> poses = placements(grid);
  // The codes of the region the circle cuts, to restore; with state.range(1),
  // bone there gets uniform noise of +-3% of its code, as a CT's bone has (the
  // phantom's tables are flat, so most of their voxels have no gradient and
  // cost the cut nothing; in a scan every voxel of bone has one).
  const Vec3 lo = poses[0].position - Vec3(12, 12, 8), hi = poses[0].position + Vec3(12, 12, 4);
  std::vector<std::pair<int64_t, VoxelCode>> saved;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-0.03, 0.03);
  for (double z = lo.z(); z <= hi.z(); z += 0.5 * grid.spacing.z())
    for (double y = lo.y(); y <= hi.y(); y += 0.5 * grid.spacing.y())
      for (double x = lo.x(); x <= hi.x(); x += 0.5 * grid.spacing.x())
        if (const int64_t v = grid.voxelOf(Vec3(x, y, z)); v >= 0) {
          VoxelCode code = grid.codes[v];
          if (state.range(1) && code > grid.isoCode) code = VoxelCode(std::lround(code * (1.0 + noise(rng))));
          saved.push_back({v, code});
        }
  for (const auto& [v, code] : saved) grid.codes[v] = code;
  grid.buildOccupancy();
  const auto restore = [&] {
    for (const auto& [v, code] : saved) grid.codes[v] = code;
    grid.buildOccupancy();
  };
  size_t k = 0;
  int64_t lowered = 0;
  TimingHistogram perCall;
  for (auto _ : state) {
    if ((k & (kPlacements - 1)) == 0 && k > 0) {
      state.PauseTiming();
      restore();
      state.ResumeTiming();
    }
    FootprintCut c;
    c.center = poses[k & (kPlacements - 1)].position - Vec3(0, 0, 1e-3 * double(state.range(0)));
    c.direction = Vec3(0, 0, -1);
    c.radius = kRadius;
    c.advance = 0.02;
    c.frame = k++;
    const auto start = std::chrono::steady_clock::now();
    lowered += cut(grid, c).lowered;
    perCall.record(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
  }
  restore();
  const TimingSummary summary = perCall.summary();  // us
  state.counters["call_p50_us"] = summary.p50;
  state.counters["call_p99_us"] = summary.p99;
  state.counters["lowered_per_call"] = double(lowered) / double(std::max<size_t>(k, 1));
}
BENCHMARK(BM_FootprintCut<cutFootprintReference>)
    ->Name("FootprintCut/reference")
    ->ArgsProduct({{0, 2000}, {0, 1}})
    ->ArgNames({"deeper_um", "noisy"});
BENCHMARK(BM_FootprintCut<cutFootprint>)->Name("FootprintCut/rows")->ArgsProduct({{0, 2000}, {0, 1}})->ArgNames({"deeper_um", "noisy"});

// The skull's surface as triangles, for the back-ends that work on meshes
// (IsoSurface.cpp): the whole phantom extracted once (ms; counters: triangles,
// blocks), and the blocks a frame's cut touches (the burr's radius plus a
// voxel around the benchmark's circle) re-extracted, us per call.
void BM_IsoSurfaceBuild(benchmark::State& state) {
  static DensityVolume volume = phantom();
  SolidGrid grid = SolidGrid::of(volume, 400.0, true);
  grid.buildOccupancy();
  BlockedIsoSurface surface;
  for (auto _ : state) surface.build(grid, grid.cellsWithoutSurface());
  state.counters["triangles"] = double(surface.triangleCount());
  state.counters["blocks"] = double(surface.blockCount());
}
BENCHMARK(BM_IsoSurfaceBuild)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_IsoSurfaceUpdate(benchmark::State& state) {
  static DensityVolume volume = phantom();
  SolidGrid grid = SolidGrid::of(volume, 400.0, true);
  grid.buildOccupancy();
  BlockedIsoSurface surface;
  surface.build(grid, grid.cellsWithoutSurface());
  const std::vector<Pose> poses = placements(grid);
  const double reach = kRadius + grid.smallestSide();  // mm, the cut's footprint
  size_t k = 0, blocks = 0;
  TimingHistogram perCall;
  for (auto _ : state) {
    const Vec3 centre = poses[k++ & (kPlacements - 1)].position;
    std::array<int64_t, 3> first{}, last{};
    for (int a = 0; a < 3; ++a) {
      first[a] = int64_t(std::floor((centre[a] - reach - grid.corner[a]) * grid.inverseSpacing[a]));
      last[a] = int64_t(std::floor((centre[a] + reach - grid.corner[a]) * grid.inverseSpacing[a]));
    }
    const auto start = std::chrono::steady_clock::now();
    blocks += surface.update(grid, first, last, grid.cellsWithoutSurface()).size();
    perCall.record(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start).count());
  }
  const TimingSummary summary = perCall.summary();  // us
  state.counters["call_p50_us"] = summary.p50;
  state.counters["call_p99_us"] = summary.p99;
  state.counters["blocks_per_call"] = double(blocks) / double(std::max<size_t>(k, 1));
}
BENCHMARK(BM_IsoSurfaceUpdate);

}  // namespace
}  // namespace trephine::bench

BENCHMARK_MAIN();
