// What removing tissue costs, in the haptic frame and on the FEM's thread,
// on the brain phantom with a tumour (22,000 tetrahedra, the resection
// scene's mesh).
//
// BM_RemoveRegion/<n>: one iteration removes a connected region of n
// tetrahedra of the tumour, grown across faces from a tetrahedron on its
// surface, as the brain does at the start of a frame: BrainResection takes
// them out with the pieces, flaps and spikes they leave (RemainingMesh), and
// the native back-end follows (LiveFaces). Manual time: only those calls are
// timed; the mesh is renewed (not timed) when the tumour is used up.
// Counters: us_per_removal, us_per_tet, tets_per_removal (with the fragments).
// BM_TLEDStepAfterRemoval/<percent>: one TLED step (double precision) after
// that share of the elements was removed; ns_per_remaining_element shows what
// the removed elements still cost the loop (their moduli are 0, their places
// kept).
// TREPHINE_BENCH_RESECTION_SMOKE=1 uses a 3,500-tetrahedron phantom.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <memory>
#include <random>
#include <set>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/BrainResection.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "plugins/tetra_brain/TetPhantoms.h"

namespace trephine::bench {
namespace {

const char* spec() {
  return std::getenv("TREPHINE_BENCH_RESECTION_SMOKE") ? "brain?tets=3500&tumour=8&tumourZ=48&detail=1.5"
                                                       : "brain?tets=22000&tumour=8&tumourZ=48&detail=1.5";
}

struct Brain {
  TetMesh mesh;
  TetTopology topology;
  tetra::TissueTable tissues;
  Brain() : mesh(tetra::makeTetPhantom(spec())), topology(mesh) {
    (void)tissues.declare({"brain", 1, 0.05, 0.03, false}, mesh.labels);
    (void)tissues.declare({"tumour", 2, 0.04, 0.12, false}, mesh.labels);
  }
};

const Brain& brain() {
  static const Brain b;
  return b;
}

// A region of up to n alive tumour tetrahedra grown across faces from one
// with a face on the surface now.
std::vector<int32_t> region(const Brain& b, const RemainingMesh& left, size_t n, std::mt19937& rng) {
  std::vector<int32_t> seeds;
  for (int32_t t = 0; t < int32_t(b.mesh.tetCount()); ++t) {
    if (!left.alive(t) || b.mesh.labels[size_t(t)] != 2) continue;
    for (int f = 0; f < 4; ++f)
      if (left.onBoundary(t, f)) {
        seeds.push_back(t);
        break;
      }
  }
  if (seeds.empty()) return {};
  std::vector<int32_t> out{seeds[std::uniform_int_distribution<size_t>(0, seeds.size() - 1)(rng)]};
  std::set<int32_t> seen(out.begin(), out.end());
  for (size_t i = 0; i < out.size() && out.size() < n; ++i)
    for (int f = 0; f < 4 && out.size() < n; ++f) {
      const int32_t m = b.topology.neighbour(out[i], f);
      if (m != kNoNeighbour && left.alive(m) && b.mesh.labels[size_t(m)] == 2 && seen.insert(m).second)
        out.push_back(m);
    }
  return out;
}

void BM_RemoveRegion(benchmark::State& state) {
  const Brain& b = brain();
  const size_t n = size_t(state.range(0));
  std::mt19937 rng(7);
  std::unique_ptr<tetra::BrainResection> resection;
  std::unique_ptr<tetra::NativeTetBackend> backend;
  auto renew = [&] {
    resection = std::make_unique<tetra::BrainResection>(b.mesh, b.topology, b.tissues);
    backend = std::make_unique<tetra::NativeTetBackend>();
    backend->bind({&b.mesh, &b.topology, {}});
    (void)backend->followRemovals();
  };
  renew();
  double removals = 0, tets = 0, seconds = 0;
  for (auto _ : state) {
    std::vector<int32_t> chosen = region(b, resection->remaining(), n, rng);
    if (chosen.size() < n) {
      renew();
      chosen = region(b, resection->remaining(), n, rng);
    }
    const auto start = std::chrono::steady_clock::now();
    resection->queue(chosen);
    size_t removed = 0;
    for (RemainingMesh::Change c = resection->removeNext(); !c.removedTets.empty(); c = resection->removeNext()) {
      backend->removeTets(c);
      removed += c.removedTets.size();
    }
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.SetIterationTime(took);
    seconds += took;
    benchmark::DoNotOptimize(removed);
    removals += 1;
    tets += double(removed);
  }
  state.counters["tets_per_removal"] = tets / std::max(1.0, removals);
  state.counters["us_per_removal"] = 1e6 * seconds / std::max(1.0, removals);
  state.counters["us_per_tet"] = 1e6 * seconds / std::max(1.0, tets);
}
BENCHMARK(BM_RemoveRegion)->Arg(1)->Arg(4)->Arg(16)->Arg(64)->UseManualTime()->Unit(benchmark::kMicrosecond);

void BM_TLEDStepAfterRemoval(benchmark::State& state) {
  const Brain& b = brain();
  const double share = double(state.range(0)) / 100.0;
  const fem::ElementMaterial material{1e-6, 30.0, 0.3};
  fem::TLEDModel model(b.mesh.nodes, b.mesh.tets, std::span(&material, 1));
  model.setTimeStep(0.5 * model.criticalTimeStep(), 50);
  std::vector<int32_t> order(b.mesh.tetCount());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int32_t(i);
  std::shuffle(order.begin(), order.end(), std::mt19937(3));
  order.resize(size_t(share * double(order.size())));
  model.removeElements(order);
  fem::TLEDState fem(model);
  for (size_t n = 0; n < b.mesh.nodeCount(); n += 97) fem.setExternalForce(int32_t(n), Vec3(0, 0, -20));
  for (auto _ : state) fem.step();
  const double remaining = double(b.mesh.tetCount() - model.removedCount());
  state.counters["ns_per_remaining_element"] = benchmark::Counter(
      double(state.iterations()) * remaining, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["ns_per_element"] = benchmark::Counter(double(state.iterations()) * double(b.mesh.tetCount()),
                                                        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_TLEDStepAfterRemoval)->Arg(0)->Arg(10)->Arg(30)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace trephine::bench

BENCHMARK_MAIN();
