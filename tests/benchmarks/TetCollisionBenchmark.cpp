// The deformable collision step split per frame (thesis Fig. 4.8 to 4.14):
//   refresh - taking the frame's node positions (and, for the thesis's scans,
//             refreshing tetrahedron boxes),
//   search  - finding the colliding shell points and their tetrahedra,
//   rest    - contact normal and penetration of those points.
// One iteration is a whole path: a 2.5 mm tool with the 211-point even shell
// pressed 1 mm into the surface along an 8 mm circle around (30, 10), 2,500
// frames (the motion of scenes/bench/tet_circle.xml, placed on the surface by
// ray casting). Per-frame times are taken with the steady clock around each
// part and reported as counters (µs): p50, p99 and max of each part, with the
// colliding points found over the path (the thesis's scans test only two rings
// of neighbours around the first colliding tetrahedron and can miss some).
//
// Arguments: mesh (Table 4.1 Cube1..7 = 0..6, Table 4.2 Brain1..5 = 7..11),
// method (0 grid, 1 first-tetrahedron, 2 previous-contact, 3 previous-contact
// refreshing only moved boxes), motion (0 rigid, 1 wave: every node moves
// every frame, 2 bump: the nodes within 15 mm of the tool move).
// --benchmark_filter='BM_TetCollisionStep/(0|7)/' keeps Cube1 and Brain1 (the smoke test).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "framework/core/Lifecycle.h"
#include "framework/geometry/ShellSampling.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "plugins/tetra_brain/TetPhantoms.h"
#include "plugins/tetra_brain/TetraBrain.h"

namespace trephine::bench {
namespace {

using tetra::TetraBrain;

struct MeshCase {
  const char* name;
  const char* spec;
};
constexpr MeshCase kMeshes[] = {
    {"Cube1", "cube?cells=7"},      {"Cube2", "cube?cells=13"},     {"Cube3", "cube?cells=22"},
    {"Cube4", "cube?cells=30"},     {"Cube5", "cube?cells=40"},     {"Cube6", "cube?cells=50"},
    {"Cube7", "cube?cells=60"},     {"Brain1", "brain?tets=3500"},  {"Brain2", "brain?tets=12500"},
    {"Brain3", "brain?tets=22000"}, {"Brain4", "brain?tets=40500"}, {"Brain5", "brain?tets=50000"}};
constexpr const char* kMethods[] = {"grid", "first-tetrahedron", "previous-contact", "previous-contact"};
constexpr const char* kMotions[] = {"rigid", "wave", "bump"};
constexpr int kFrames = 2500;
constexpr double kToolRadius = 2.5, kPress = 1.0, kCircleRadius = 8.0;  // mm

// What TetraBrain::init needs from the framework, without a scene.
class BenchInitContext final : public InitContext {
 public:
  void error(const Component&, std::string message) override { errors += message + "\n"; }
  void error(const BaseField&, std::string message) override { errors += message + "\n"; }
  uint64_t seed() const override { return 0; }
  bool isRealtime() const override { return false; }
  ChannelHub& channels() override { return hub; }
  EventLog& events() override { return log; }
  HapticFrameLog* claimHapticLog(const Component&, bool) override { return nullptr; }
  std::unique_ptr<CollisionBackend> createBackend(std::string_view kind, std::string_view name) override {
    if (kind == "TetraBrain" && name == "native") return std::make_unique<tetra::NativeTetBackend>();
    return nullptr;
  }
  ChannelHub hub;
  EventLog log{16};
  std::string errors;
};

void assign(Component& component, const std::string& field, const std::string& value) {
  for (BaseField* f : component.fields())
    if (f->name() == field) {
      if (auto error = f->assign(value, ParseContext{}, SourceLocation{"bench", 0, 0}))
        throw std::runtime_error(field + ": " + *error);
      return;
    }
  throw std::runtime_error("no field " + field);
}

struct Percentiles {
  double p50 = 0, p99 = 0, max = 0;
};
Percentiles percentiles(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  auto at = [&](double q) { return v[std::min(v.size() - 1, size_t(q * double(v.size())))]; };
  return {at(0.5), at(0.99), v.back()};
}

void BM_TetCollisionStep(benchmark::State& state) {
  const MeshCase& mesh = kMeshes[state.range(0)];
  const int method = int(state.range(1)), motion = int(state.range(2));
  state.SetLabel(std::string(mesh.name) + "/" + kMethods[method] + (method == 3 ? "+moved" : "") + "/" +
                 kMotions[motion]);

  BenchInitContext context;
  TetraBrain brain;
  assign(brain, "file", std::string("phantom:") + mesh.spec);
  assign(brain, "search", kMethods[method]);
  if (method > 0) assign(brain, "boxRefresh", method == 3 ? "moved" : "all");
  brain.init(context);
  if (!context.errors.empty()) {
    state.SkipWithError(context.errors.c_str());
    return;
  }
  std::vector<ShellPoint> shell;
  for (const Vec3& d : evenDirections(211)) shell.push_back({kToolRadius * d, -d});
  brain.reserveShell(shell);
  auto& native = dynamic_cast<tetra::NativeTetBackend&>(*brain.backend());

  // The path: around (30, 10), each pose placed on the surface found below it.
  std::vector<Pose> poses;
  const double top = brain.bounds().max().z() + 10;
  for (int k = 0; k < kFrames; ++k) {
    const double a = 2 * std::numbers::pi * 1.55 * k / kFrames;
    const Vec3 above(30 + kCircleRadius * std::cos(a), 10 + kCircleRadius * std::sin(a), top);
    const auto hit = brain.raycast(above, Vec3(0, 0, -1), 1e4);
    if (!hit) continue;
    poses.push_back({hit->point + (kToolRadius - kPress) * hit->normal, Quat::Identity()});
  }

  // The deformation: this benchmark publishes the node positions itself.
  Component producer;
  Channel<NodePositions>& channel =
      context.hub.publish<NodePositions>(producer, kNodePositionsChannel);
  const std::vector<Vec3> rest = brain.mesh().nodes;
  NodePositions frame;
  std::vector<double> profile(rest.size());
  const Vec3 centre(30, 10, brain.bounds().max().z());
  if (motion > 0) {
    if (brain.followDeformation(producer, context.hub)) {
      state.SkipWithError("could not follow");
      return;
    }
    frame.positions = rest;
    frame.displacementBound = 0.5;  // mm
    frame.allMoved = motion == 1;
    for (size_t i = 0; i < rest.size(); ++i) {
      const double r = (rest[i] - centre).norm();
      profile[i] = motion == 1 ? 2 * std::numbers::pi * r / 40.0 : std::pow(std::max(0.0, 1 - (r / 15) * (r / 15)), 2);
      if (motion == 2 && r < 15) frame.movedNodes.push_back(int32_t(i));
    }
  }

  using Clock = std::chrono::steady_clock;
  auto us = [](Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); };
  std::vector<double> refreshUs, searchUs, restUs, totalUs;
  size_t contacts = 0, points = 0;
  double frameTime = 0;  // s, a new frame per pose
  for (auto _ : state) {
    refreshUs.clear(), searchUs.clear(), restUs.clear(), totalUs.clear();
    contacts = 0, points = 0;
    for (size_t k = 0; k < poses.size(); ++k) {
      if (motion > 0) {                                                  // untimed: the deformation's own work
        const double phase = 2 * std::numbers::pi * double(k) / 1000.0;  // 1 Hz at 1 kHz
        if (motion == 1) {
          for (size_t i = 0; i < rest.size(); ++i)
            frame.positions[i] = rest[i] + 0.5 * std::sin(profile[i] - phase) * Vec3::UnitZ();
        } else {
          for (int32_t i : frame.movedNodes)
            frame.positions[i] = rest[i] + 0.5 * std::sin(phase) * profile[i] * Vec3::UnitZ();
        }
        ++frame.step;
        channel.publish(frame);
      }
      const auto t0 = Clock::now();
      brain.beginFrame(frameTime += 1e-3);
      const auto t1 = Clock::now();
      const std::span<tetra::TetHit> hits = native.findHits(poses[k], shell);
      const auto t2 = Clock::now();
      const ShellContact c =
          native.contactOfHits(poses[k], shell, hits, false).contact;  // collide() is these two calls
      const auto t3 = Clock::now();
      benchmark::DoNotOptimize(c);
      contacts += c.points > 0;
      points += size_t(c.points);
      refreshUs.push_back(us(t1 - t0));
      searchUs.push_back(us(t2 - t1));
      restUs.push_back(us(t3 - t2));
      totalUs.push_back(us(t3 - t0));
    }
  }
  const auto add = [&](const char* name, const std::vector<double>& v) {
    const Percentiles p = percentiles(v);
    state.counters[std::string(name) + "_p50_us"] = p.p50;
    state.counters[std::string(name) + "_p99_us"] = p.p99;
    state.counters[std::string(name) + "_max_us"] = p.max;
  };
  add("refresh", refreshUs);
  add("search", searchUs);
  add("rest", restUs);
  add("total", totalUs);
  state.counters["frames"] = double(poses.size());
  state.counters["contact_frames"] = double(contacts);
  // Summed over the path: a search that misses colliding points finds fewer.
  state.counters["colliding_points"] = double(points);
  state.counters["tetrahedra"] = double(brain.mesh().tetCount());
}

void arguments(benchmark::internal::Benchmark* b) {
  for (int mesh = 0; mesh < 12; ++mesh) {
    for (int method = 0; method < 3; ++method) b->Args({mesh, method, 0});  // rigid: the thesis's experiments
    b->Args({mesh, 0, 1});                                                  // every node moves: the grid,
    b->Args({mesh, 2, 1});                                                  // the thesis refreshing every box,
    b->Args({mesh, 2, 2});                                                  // a local bump: all boxes
    b->Args({mesh, 3, 2});                                                  // or only the moved ones
  }
}
BENCHMARK(BM_TetCollisionStep)->Apply(arguments)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace trephine::bench
BENCHMARK_MAIN();
