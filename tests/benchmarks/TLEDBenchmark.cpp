// The TLED step (plugins/fem) on the brain phantoms of Table 4.2 and on the
// cube of Table 4.1, against this machine's own limits, measured in the same
// run: STREAM's triad (memory bandwidth of one core) and a chain of fused
// multiply-adds (peak double-precision flops of one core).
//
// BM_TLEDStep/<mesh>/<precision>/<isa>: one iteration is one time step
// (element loop and central-difference update) of the FEM with the thesis's
// material (Table 6.1), at rest plus a pressed dent so that the stresses are
// not zero; the element loop in double (precision 0) or single precision (1),
// compiled for AVX2 (isa 1) or AVX-512 (2), each where the processor has it.
// Counters: steps_per_s, ns_per_element_step, GB_per_s (the bytes a step
// must move: element arrays, node arrays), GFLOP_per_s (264 flops per
// element), critical_dt_us and the real-time factor at the thesis's 0.33 ms
// step, or at the mesh's own critical step when it is shorter.
// BM_VonMisesStress/<mesh>: one iteration computes every element's von Mises
// stress (what the FEM publishes for a viewer, at most every stressInterval),
// on the dented shape after 200 steps; ns_per_element and its share of a
// double-precision step of the same mesh run are the counters.
// TREPHINE_BENCH_TLED_SMOKE=1 keeps the smallest brain (the smoke test).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"
#include "plugins/tetra_brain/TetPhantoms.h"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace trephine::bench {
namespace {

struct MeshCase {
  const char* name;
  const char* spec;
};
constexpr MeshCase kMeshes[] = {{"Brain1", "brain?tets=3500"},   {"Brain2", "brain?tets=12500"},
                                {"Brain3", "brain?tets=22000"},  {"Brain4", "brain?tets=40500"},
                                {"Brain5", "brain?tets=50000"},  {"Cube3", "cube?cells=22"}};

// Flops per element of TLEDKernel.cpp, counted from its loops: gather 9,
// F 57, J 14, I1 18, guess 6, four Newton steps 24, stress factors 8,
// cofactor 27, V P 36, forces 45, scatter 21.
constexpr double kFlopsPerElement = 265;
constexpr double kThesisStep = 0.33e-3;  // s

struct Model {
  std::unique_ptr<fem::TLEDModel> model;
};

Model& modelFor(int index) {
  static Model models[std::size(kMeshes)];
  Model& m = models[index];
  if (!m.model) {
    const TetMesh mesh = tetra::makeTetPhantom(kMeshes[index].spec);
    const fem::ElementMaterial material{};  // Table 6.1
    m.model = std::make_unique<fem::TLEDModel>(mesh.nodes, mesh.tets, std::span(&material, 1));
    // A dent: the nodes within 15 mm of the top pushed 3 mm down, held.
    Vec3 top = mesh.nodes[0];
    for (const Vec3& p : mesh.nodes)
      if (p.z() > top.z()) top = p;
    for (size_t i = 0; i < mesh.nodeCount(); ++i)
      if ((mesh.nodes[i] - top).norm() < 15) m.model->fixNode(int32_t(i), Vec3(0, 0, -3));
  }
  return m;
}

void BM_TLEDStep(benchmark::State& state) {
  fem::TLEDModel& model = *modelFor(int(state.range(0))).model;
  const bool single = state.range(1) == 1;
  const auto isa = fem::ElementLoopIsa(state.range(2));
  model.setElementPrecision(single ? fem::ElementPrecision::kSingle : fem::ElementPrecision::kDouble);
  model.setElementLoopIsa(isa);
  const double critical = model.criticalTimeStep(50);
  model.setTimeStep(std::min(kThesisStep, 0.9 * critical), 50);
  fem::TLEDState moving(model);  // from rest, the dent held
  for (auto _ : state) moving.step();
  const double elements = double(model.elementCount()), nodes = double(model.nodeCount());
  const double steps = double(state.iterations());
  // Bytes per step: per element 4 indices, 9 gradients and 2 moduli (88 B
  // in double, 60 B in single); per node the update reads u, u-, f, f_ext,
  // free, held, scale and writes u+ on three axes, and the element loop
  // reads u and writes f (about 220 B).
  const double bytes = (single ? 60 : 88) * elements + 220 * nodes;
  state.counters["elements"] = elements;
  state.counters["nodes"] = nodes;
  state.counters["steps_per_s"] = benchmark::Counter(steps, benchmark::Counter::kIsRate);
  state.counters["ns_per_element_step"] =
      benchmark::Counter(steps * elements * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["GB_per_s"] = benchmark::Counter(steps * bytes * 1e-9, benchmark::Counter::kIsRate);
  state.counters["GFLOP_per_s"] = benchmark::Counter(steps * elements * kFlopsPerElement * 1e-9,
                                                     benchmark::Counter::kIsRate);
  state.counters["critical_dt_us"] = critical * 1e6;
  state.counters["dt_us"] = model.timeStep() * 1e6;
  // Simulated seconds per wall second at that step.
  state.counters["realtime_factor"] = benchmark::Counter(steps * model.timeStep(), benchmark::Counter::kIsRate);
  state.SetLabel(std::string(kMeshes[state.range(0)].name) + (single ? " single " : " double ") +
                 fem::elementLoopName(isa));
}

void BM_VonMisesStress(benchmark::State& state) {
  fem::TLEDModel& model = *modelFor(int(state.range(0))).model;
  model.setElementPrecision(fem::ElementPrecision::kDouble);
  model.setElementLoopIsa(fem::bestElementLoopIsa());
  model.setTimeStep(std::min(kThesisStep, 0.9 * model.criticalTimeStep(50)), 50);
  fem::TLEDState dented(model);
  for (int i = 0; i < 200; ++i) dented.step();
  std::vector<float> stress(model.elementCount());
  for (auto _ : state) {
    dented.vonMisesStress(stress);
    benchmark::DoNotOptimize(stress.data());
  }
  const double elements = double(model.elementCount());
  state.counters["elements"] = elements;
  state.counters["ns_per_element"] = benchmark::Counter(double(state.iterations()) * elements * 1e-9,
                                                        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetLabel(kMeshes[state.range(0)].name);
}

// STREAM triad a = b + s c on 3 x 80 MB, one core.
void BM_StreamTriad(benchmark::State& state) {
  const size_t n = size_t(10) << 20;
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  for (auto _ : state) {
    const double s = 3.0;
    for (size_t i = 0; i < n; ++i) a[i] = b[i] + s * c[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.counters["GB_per_s"] = benchmark::Counter(double(state.iterations()) * 3 * 8 * double(n) * 1e-9,
                                                  benchmark::Counter::kIsRate);
}

#if defined(__x86_64__) && defined(__GNUC__)
// Ten independent chains of AVX2 fused multiply-adds (4 doubles, 2 flops each),
// enough to cover the instruction's latency on two ports.
__attribute__((target("avx2,fma"), noinline)) double fmaChains(int64_t rounds) {
  __m256d acc[10];
  for (int k = 0; k < 10; ++k) acc[k] = _mm256_set1_pd(1.0 + k * 1e-3);
  const __m256d x = _mm256_set1_pd(0.999999), y = _mm256_set1_pd(1e-7);
  for (int64_t r = 0; r < rounds; ++r)
    for (int k = 0; k < 10; ++k) acc[k] = _mm256_fmadd_pd(acc[k], x, y);
  __m256d sum = acc[0];
  for (int k = 1; k < 10; ++k) sum = _mm256_add_pd(sum, acc[k]);
  double out[4];
  _mm256_storeu_pd(out, sum);
  return out[0] + out[1] + out[2] + out[3];
}

void BM_PeakFlops(benchmark::State& state) {
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
    state.SkipWithError("no AVX2 and FMA");
    return;
  }
  int64_t rounds = 1 << 22;
  for (auto _ : state) {
    benchmark::DoNotOptimize(rounds);  // not a constant: the call cannot be hoisted out of the loop
    benchmark::DoNotOptimize(fmaChains(rounds));
  }
  state.counters["GFLOP_per_s"] =
      benchmark::Counter(double(state.iterations()) * double(rounds) * 10 * 4 * 2 * 1e-9, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PeakFlops)->Unit(benchmark::kMillisecond);
#endif

BENCHMARK(BM_StreamTriad)->Unit(benchmark::kMillisecond);

void registerSteps() {
  const bool smoke = std::getenv("TREPHINE_BENCH_TLED_SMOKE") != nullptr;
  for (int i = 0; i < int(std::size(kMeshes)); ++i) {
    if (smoke && i > 0) break;
    for (int precision : {0, 1})
      for (fem::ElementLoopIsa isa : {fem::ElementLoopIsa::kAvx2, fem::ElementLoopIsa::kAvx512})
        if (fem::elementLoopAvailable(isa))
          benchmark::RegisterBenchmark("BM_TLEDStep", BM_TLEDStep)
              ->Args({i, precision, int(isa)})
              ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark("BM_VonMisesStress", BM_VonMisesStress)->Args({i})->Unit(benchmark::kMicrosecond);
  }
}

}  // namespace
}  // namespace trephine::bench

int main(int argc, char** argv) {
  trephine::bench::registerSteps();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
