// The element loop of TLED, the hot spot of the FEM: per element, the
// deformation gradient from the nodal displacements, the neo-Hookean stress
// and the four internal nodal forces (NeoHookean.h gives the formulas).
//
// Elements are taken in chunks: the displacements of a chunk's nodes are
// gathered into arrays, the arithmetic runs over those arrays in branch-free
// loops the compiler vectorises (about 190 floating-point operations per
// element), and the forces are scattered back to the nodes. J^(-1/3) comes
// from a quadratic guess and four Newton steps, exact to rounding for J in
// [0.6, 1.6]; the few elements deformed beyond that range take std::cbrt in a
// scalar pass, so the library's transcendental function never runs for an
// element near rest. The loop is compiled twice, for the baseline instruction
// set and for AVX2 with FMA, and the faster one this processor runs is picked
// once.
#include <algorithm>
#include <cmath>

#include "plugins/fem/TledModel.h"

namespace trephine::fem {

namespace {

constexpr size_t kChunk = 64;  // elements per pass: the scratch below stays in L1 (about 30 KB)
constexpr double kFastLow = 0.6, kFastHigh = 1.6;

struct ChunkScratch {
  // d[3 (a - 1) + i]: displacement of local node a less node 0's, axis i (mm).
  alignas(64) double d[9][kChunk];
  alignas(64) double F[9][kChunk];  // row-major deformation gradient
  alignas(64) double J[kChunk];
  alignas(64) double I1[kChunk];
  alignas(64) double y[kChunk];  // J^(-1/3), with J clamped below at kMinIsochoricJ
  alignas(64) double f[9][kChunk];  // forces on local nodes 1..3 (node 0 takes minus their sum), mN
};

[[gnu::always_inline]] inline ElementStepCounts forcesOfAllElements(const TledElements& el, const double* ux,
                                                                   const double* uy, const double* uz, double* fx,
                                                                   double* fy, double* fz) {
  ElementStepCounts counts;
  ChunkScratch s;
  for (size_t base = 0; base < el.padded; base += kChunk) {
    const size_t n = std::min(kChunk, el.padded - base);
    // Gather.
    for (size_t e = 0; e < n; ++e) {
      const int32_t n0 = el.node[0][base + e];
      for (int a = 1; a < 4; ++a) {
        const int32_t na = el.node[a][base + e];
        s.d[3 * (a - 1) + 0][e] = ux[na] - ux[n0];
        s.d[3 * (a - 1) + 1][e] = uy[na] - uy[n0];
        s.d[3 * (a - 1) + 2][e] = uz[na] - uz[n0];
      }
    }
    // F = I + sum_a d_a grad_a^T, J, I1 and the fast J^(-1/3).
    const double* g[9];
    for (int k = 0; k < 9; ++k) g[k] = el.grad[k].data() + base;
    for (size_t e = 0; e < n; ++e) {
      double F[9];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          F[3 * i + j] = (i == j ? 1.0 : 0.0) + s.d[i][e] * g[j][e] + s.d[3 + i][e] * g[3 + j][e] +
                         s.d[6 + i][e] * g[6 + j][e];
      const double J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
                       F[2] * (F[3] * F[7] - F[4] * F[6]);
      double I1 = 0;
      for (int k = 0; k < 9; ++k) {
        s.F[k][e] = F[k];
        I1 += F[k] * F[k];
      }
      s.J[e] = J;
      s.I1[e] = I1;
      const double x = J - 1;
      double y = 1 - x / 3 + 2 * x * x / 9;
      for (int it = 0; it < 4; ++it) y = y * (4 - J * y * y * y) * (1.0 / 3.0);
      s.y[e] = y;
    }
    // Elements far from rest: the exact root (scalar, rare).
    for (size_t e = 0; e < n; ++e) {
      const double J = s.J[e];
      if (J >= kFastLow && J <= kFastHigh) continue;
      ++counts.farFromRest;
      if (!(J > 0)) ++counts.inverted;
      s.y[e] = 1.0 / std::cbrt(std::max(J, kMinIsochoricJ));
    }
    // P = mu J^(-2/3) F + (kappa (J - 1) - mu I1 J^(-5/3) / 3) cof F; f_a = V P grad_a.
    const double* volume = el.volume.data() + base;
    const double* mu = el.mu.data() + base;
    const double* kappa = el.kappa.data() + base;
    for (size_t e = 0; e < n; ++e) {
      double F[9];
      for (int k = 0; k < 9; ++k) F[k] = s.F[k][e];
      const double J = s.J[e];
      const double Jiso = std::max(J, kMinIsochoricJ);
      const double y2 = s.y[e] * s.y[e];  // J^(-2/3)
      const double isochoric = mu[e] * y2;
      const double onCofactor = kappa[e] * (J - 1) - isochoric * s.I1[e] / (3 * Jiso);
      const double cof[9] = {F[4] * F[8] - F[5] * F[7], F[5] * F[6] - F[3] * F[8], F[3] * F[7] - F[4] * F[6],
                             F[2] * F[7] - F[1] * F[8], F[0] * F[8] - F[2] * F[6], F[1] * F[6] - F[0] * F[7],
                             F[1] * F[5] - F[2] * F[4], F[2] * F[3] - F[0] * F[5], F[0] * F[4] - F[1] * F[3]};
      double VP[9];
      for (int k = 0; k < 9; ++k) VP[k] = volume[e] * (isochoric * F[k] + onCofactor * cof[k]);
      for (int a = 0; a < 3; ++a)
        for (int i = 0; i < 3; ++i)
          s.f[3 * a + i][e] =
              VP[3 * i] * g[3 * a][e] + VP[3 * i + 1] * g[3 * a + 1][e] + VP[3 * i + 2] * g[3 * a + 2][e];
    }
    // Scatter.
    for (size_t e = 0; e < n; ++e) {
      const int32_t n0 = el.node[0][base + e];
      double sx = 0, sy = 0, sz = 0;
      for (int a = 1; a < 4; ++a) {
        const int32_t na = el.node[a][base + e];
        const double ax = s.f[3 * (a - 1)][e], ay = s.f[3 * (a - 1) + 1][e], az = s.f[3 * (a - 1) + 2][e];
        fx[na] += ax;
        fy[na] += ay;
        fz[na] += az;
        sx += ax;
        sy += ay;
        sz += az;
      }
      fx[n0] -= sx;
      fy[n0] -= sy;
      fz[n0] -= sz;
    }
  }
  return counts;
}

ElementStepCounts forcesBaseline(const TledElements& el, const double* ux, const double* uy, const double* uz,
                                 double* fx, double* fy, double* fz) {
  return forcesOfAllElements(el, ux, uy, uz, fx, fy, fz);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,fma"))) ElementStepCounts forcesAvx2(const TledElements& el, const double* ux,
                                                                  const double* uy, const double* uz, double* fx,
                                                                  double* fy, double* fz) {
  return forcesOfAllElements(el, ux, uy, uz, fx, fy, fz);
}
#endif

using ForcesFunction = ElementStepCounts (*)(const TledElements&, const double*, const double*, const double*,
                                             double*, double*, double*);

ForcesFunction pickForces() {
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return forcesAvx2;
#endif
  return forcesBaseline;
}

}  // namespace

ElementStepCounts accumulateInternalForces(const TledElements& elements, const double* ux, const double* uy,
                                           const double* uz, double* fx, double* fy, double* fz) {
  static const ForcesFunction forces = pickForces();
  return forces(elements, ux, uy, uz, fx, fy, fz);
}

}  // namespace trephine::fem
