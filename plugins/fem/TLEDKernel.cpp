// The element loop of TLED, the hot spot of the FEM: per element, the
// deformation gradient from the nodal displacements, the neo-Hookean stress
// and the four internal nodal forces (NeoHookean.h gives the formulas).
//
// Elements are taken in chunks of 64 (the model pads them to whole chunks):
// the displacements of a chunk's nodes are gathered into arrays, the
// arithmetic runs over those arrays in branch-free loops the compiler
// vectorises (about 250 floating-point operations per element), and the
// forces are scattered back to the nodes.
// J^(-1/3) comes from its cubic Taylor polynomial and three Newton steps,
// exact to rounding for J in [0.65, 1.5]; the few elements deformed beyond
// that take std::cbrt in a scalar pass, so the library's transcendental
// function never runs for an element near rest. The arithmetic runs in
// double or, when the model asks for it, in single precision (the thesis's GPU
// code ran in single precision): twice the lanes and half the element bytes;
// the node vectors, their differences and the sums into the nodes stay in
// double either way. Compiled three times: for the baseline instruction set,
// for AVX2 with FMA (a node's (x, y, z, 0) is one 256-bit load or store, and
// four elements' nodes are transposed in registers) and with the arithmetic
// on AVX-512 vectors; the model runs the best one the processor has.
#include <algorithm>
#include <cmath>
#include <type_traits>

#include <Eigen/SVD>

#include "plugins/fem/TLEDModel.h"

#if defined(__x86_64__) && defined(__GNUC__)
// GCC 12's AVX-512 intrinsics pass a deliberately undefined merge operand,
// which -Wmaybe-uninitialized reports wherever they are inlined (GCC bug
// 105593); the reports point into the header, so silencing them there is enough.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#define TREPHINE_TLED_AVX2 1
#endif

namespace trephine::fem {

namespace {

constexpr size_t kChunk = 64;  // elements per pass: the scratch below stays in L1 (about 30 KB)
constexpr double kFastLow = 0.65, kFastHigh = 1.5;
// The least principal stretch an element's stress is taken at (invertibleForcesOfChunk).
constexpr double kLeastStretch = 0.25;
static_assert(kChunk == TLEDElements::kLanes && kChunk % 16 == 0);  // whole chunks, whole vectors

// T: the precision of the element arithmetic (double or float).
template <typename T>
struct ChunkScratch {
  // d[3 (a - 1) + i]: displacement of local node a less node 0's, axis i (mm).
  alignas(64) T d[9][kChunk];
  alignas(64) T F[9][kChunk];  // row-major deformation gradient
  alignas(64) T J[kChunk];
  alignas(64) T I1[kChunk];
  alignas(64) T y[kChunk];     // J^(-1/3), with J clamped below at kMinIsochoricJ
  alignas(64) T f[9][kChunk];  // forces on local nodes 1..3 (node 0 takes minus their sum), mN
};

// The element arrays in the arithmetic's precision.
template <typename T>
struct ElementArrays {
  const T* grad[9];
  const T* muVolume;
  const T* kappaVolume;
  explicit ElementArrays(const TLEDElements& el) {
    if constexpr (std::is_same_v<T, double>) {
      for (int k = 0; k < 9; ++k) grad[k] = el.grad[k].data();
      muVolume = el.muVolume.data();
      kappaVolume = el.kappaVolume.data();
    } else {
      for (int k = 0; k < 9; ++k) grad[k] = el.single.grad[k].data();
      muVolume = el.single.muVolume.data();
      kappaVolume = el.single.kappaVolume.data();
    }
  }
};

// The scatter takes a chunk's groups of four elements in this order: 0, 4,
// 8, 12, 1, 5, ... Neighbouring groups share nodes, and the addition into a
// node waits for the previous addition's store; groups four apart rarely
// share one. (Measured on the brain phantoms: the step 7 to 10% faster than
// in order.)
constexpr size_t scatterGroup(size_t g) { return (g * 4) % (kChunk / 4) + (g * 4) / (kChunk / 4); }

// ---- gather and scatter, portable --------------------------------------------

template <typename T>
[[gnu::always_inline]] inline void gatherScalar(const TLEDElements& el, size_t base, const double* u,
                                                ChunkScratch<T>& s) {
  for (size_t e = 0; e < kChunk; ++e) {
    const double* u0 = u + size_t(el.nodeOffset[0][base + e]);
    for (int a = 1; a < 4; ++a) {
      const double* ua = u + size_t(el.nodeOffset[a][base + e]);
      for (int i = 0; i < 3; ++i) s.d[3 * (a - 1) + i][e] = T(ua[i] - u0[i]);
    }
  }
}

template <typename T>
[[gnu::always_inline]] inline void scatterScalar(const TLEDElements& el, size_t base,
                                                 const ChunkScratch<T>& s, double* f) {
  for (size_t i = 0; i < kChunk; ++i) {
    const size_t e = 4 * scatterGroup(i / 4) + i % 4;
    double* f0 = f + size_t(el.nodeOffset[0][base + e]);
    for (int a = 1; a < 4; ++a) {
      double* fa = f + size_t(el.nodeOffset[a][base + e]);
      for (int i = 0; i < 3; ++i) {
        const double force = s.f[3 * (a - 1) + i][e];
        fa[i] += force;
        f0[i] -= force;
      }
    }
  }
}

// ---- the arithmetic, shared by both versions ---------------------------------

// F = I + sum_a d_a grad_a^T, J, I1 and the fast J^(-1/3); then the exact root
// where J is far from 1. Returns the counts of the chunk.
template <typename T>
[[gnu::always_inline]] inline ElementStepCounts strainOfChunk(const ElementArrays<T>& el, size_t base,
                                                              ChunkScratch<T>& s) {
  const T* g[9];
  for (int k = 0; k < 9; ++k) g[k] = el.grad[k] + base;
  for (size_t e = 0; e < kChunk; ++e) {
    T F[9];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        F[3 * i + j] = (i == j ? T(1) : T(0)) + s.d[i][e] * g[j][e] + s.d[3 + i][e] * g[3 + j][e] +
                       s.d[6 + i][e] * g[6 + j][e];
    const T J = F[0] * (F[4] * F[8] - F[5] * F[7]) - F[1] * (F[3] * F[8] - F[5] * F[6]) +
                F[2] * (F[3] * F[7] - F[4] * F[6]);
    T I1 = 0;
    for (int k = 0; k < 9; ++k) {
      s.F[k][e] = F[k];
      I1 += F[k] * F[k];
    }
    s.J[e] = J;
    s.I1[e] = I1;
    // Products by 1/3 and 1/81, not divisions: the compiler may not turn a
    // division by 3 into a product itself (1/3 is not exact).
    constexpr T kThird = T(1.0 / 3.0);
    const T x = J - 1;
    T y = 1 + x * (-kThird + x * (T(2.0 / 9.0) - x * T(14.0 / 81.0)));
    // Newton on y^-3 = J: y (4 - J y^3) / 3, written so that its chain of
    // dependent operations is three deep, not six.
    for (int it = 0; it < 3; ++it) {
      const T cubeTimesJ = (y * y) * (y * J);
      y = (4 * kThird) * y - (kThird * y) * cubeTimesJ;
    }
    s.y[e] = y;
  }
  ElementStepCounts counts;
  for (size_t e = 0; e < kChunk; ++e) {
    const T J = s.J[e];
    if (J >= T(kFastLow) && J <= T(kFastHigh)) continue;
    // A removed element (resection) has no moduli: its shape is no one's.
    const bool counted = el.muVolume[base + e] != T(0) || el.kappaVolume[base + e] != T(0);
    counts.farFromRest += counted;
    if (!(J > 0)) counts.inverted += counted;
    s.y[e] = T(1) / std::cbrt(std::max(J, T(kMinIsochoricJ)));
  }
  return counts;
}

// P V = mu V J^(-2/3) F + (kappa V (J - 1) - mu V I1 J^(-5/3) / 3) cof F; f_a = P V grad_a.
template <typename T>
[[gnu::always_inline]] inline void forcesOfChunk(const ElementArrays<T>& el, size_t base,
                                                 ChunkScratch<T>& s) {
  const T* g[9];
  for (int k = 0; k < 9; ++k) g[k] = el.grad[k] + base;
  const T* mu = el.muVolume + base;  // the rest volume is in the moduli
  const T* kappa = el.kappaVolume + base;
  for (size_t e = 0; e < kChunk; ++e) {
    T F[9];
    for (int k = 0; k < 9; ++k) F[k] = s.F[k][e];
    const T J = s.J[e];
    const T y = s.y[e], y2 = y * y;  // J^(-1/3), J^(-2/3)
    const T isochoric = mu[e] * y2;
    // mu I1 J^(-5/3) / 3 with J^(-5/3) = y^5: no division (and no select,
    // which would stop the vectoriser), the clamp of J already in y.
    const T onCofactor = kappa[e] * (J - 1) - isochoric * (y2 * y) * s.I1[e] * T(1.0 / 3.0);
    const T cof[9] = {F[4] * F[8] - F[5] * F[7], F[5] * F[6] - F[3] * F[8], F[3] * F[7] - F[4] * F[6],
                      F[2] * F[7] - F[1] * F[8], F[0] * F[8] - F[2] * F[6], F[1] * F[6] - F[0] * F[7],
                      F[1] * F[5] - F[2] * F[4], F[2] * F[3] - F[0] * F[5], F[0] * F[4] - F[1] * F[3]};
    T P[9];
    for (int k = 0; k < 9; ++k) P[k] = isochoric * F[k] + onCofactor * cof[k];
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < 3; ++i)
        s.f[3 * a + i][e] = P[3 * i] * g[3 * a][e] + P[3 * i + 1] * g[3 * a + 1][e] + P[3 * i + 2] * g[3 * a + 2][e];
  }
}

// Elements far from rest again, in double precision: the forces of the
// singular values of F, each at least kLeastStretch (Irving, Teran and Fedkiw,
// "Invertible finite elements for robust simulation of large deformation",
// 2004). F = U diag(s) V^T with U and V rotations (a reflection turns the
// smallest singular value negative: an inverted element); P = U diag(p) V^T,
// p_i = mu J^(-2/3) (s_i - I1 / (3 s_i)) + kappa (J - 1) J / s_i, the same
// neo-Hookean stress as above where every s_i >= kLeastStretch. An element
// squeezed flat or inverted then pushes back as hard as one squeezed to
// kLeastStretch, in the direction that restores it, instead of having a
// clamped isochoric stress that lets a tool drag its node through it.
template <typename T>
void invertibleForcesOfChunk(const ElementArrays<T>& el, size_t base, ChunkScratch<T>& s) {
  const T* g[9];
  for (int k = 0; k < 9; ++k) g[k] = el.grad[k] + base;
  for (size_t e = 0; e < kChunk; ++e) {
    const T Jfast = s.J[e];
    if (Jfast >= T(kFastLow) && Jfast <= T(kFastHigh)) continue;
    const double mu = double(el.muVolume[base + e]), kappa = double(el.kappaVolume[base + e]);
    if (mu == 0 && kappa == 0) continue;  // removed, or padding
    // No SVD where the smallest stretch is surely above the least: it is at
    // least J / (s_max s_mid) >= 2 J / I1 (as s_max s_mid <= (s_max^2 + s_mid^2) / 2).
    if (Jfast > 0 && 2 * double(Jfast) >= kLeastStretch * double(s.I1[e])) continue;
    Mat3 F;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) F(i, j) = double(s.F[3 * i + j][e]);
    if (!F.allFinite()) continue;
    const Eigen::JacobiSVD<Mat3> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 U = svd.matrixU(), V = svd.matrixV();
    Vec3 stretch = svd.singularValues();
    if (U.determinant() < 0) {
      U.col(2) *= -1;
      stretch(2) *= -1;
    }
    if (V.determinant() < 0) {
      V.col(2) *= -1;
      stretch(2) *= -1;
    }
    if (stretch.minCoeff() >= kLeastStretch) continue;  // the formula above holds
    for (int i = 0; i < 3; ++i) stretch(i) = std::max(stretch(i), kLeastStretch);
    const double J = stretch.prod(), I1 = stretch.squaredNorm();
    const double isochoric = mu * std::pow(J, -2.0 / 3.0);
    Vec3 principal;
    for (int i = 0; i < 3; ++i)
      principal(i) = isochoric * (stretch(i) - I1 / (3 * stretch(i))) + kappa * (J - 1) * J / stretch(i);
    const Mat3 P = U * principal.asDiagonal() * V.transpose();
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < 3; ++i)
        s.f[3 * a + i][e] = T(P(i, 0) * double(g[3 * a][e]) + P(i, 1) * double(g[3 * a + 1][e]) +
                              P(i, 2) * double(g[3 * a + 2][e]));
  }
}

// The arithmetic of a gathered chunk, the same in every version; adds the chunk's counts.
template <typename T>
[[gnu::always_inline]] inline void forcesOfGatheredChunk(const ElementArrays<T>& arrays, size_t base,
                                                         ChunkScratch<T>& s, ElementStepCounts& counts) {
  const ElementStepCounts chunk = strainOfChunk(arrays, base, s);
  counts.inverted += chunk.inverted;
  counts.farFromRest += chunk.farFromRest;
  forcesOfChunk(arrays, base, s);
  if (chunk.farFromRest > 0) invertibleForcesOfChunk(arrays, base, s);
}

// ---- the versions: baseline, AVX2, AVX-512 ---------------------------------------

template <typename T>
ElementStepCounts forcesBaseline(const TLEDElements& el, const double* u, double* f) {
  ElementStepCounts counts;
  ChunkScratch<T> s;
  const ElementArrays<T> arrays(el);
  for (size_t base = 0; base < el.padded; base += kChunk) {
    gatherScalar(el, base, u, s);
    forcesOfGatheredChunk(arrays, base, s, counts);
    scatterScalar(el, base, s, f);
  }
  return counts;
}

#ifdef TREPHINE_TLED_AVX2
// Rows r0..r3 (one per element: x, y, z, 0) to columns (x of the four, y, z).
__attribute__((target("avx2,fma"), always_inline)) inline void transposeToColumns(__m256d r0, __m256d r1, __m256d r2,
                                                                                 __m256d r3, __m256d& x, __m256d& y,
                                                                                 __m256d& z) {
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1);  // x0 x1 z0 z1
  const __m256d t1 = _mm256_unpackhi_pd(r0, r1);  // y0 y1 0 0
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3);  // x2 x3 z2 z3
  const __m256d t3 = _mm256_unpackhi_pd(r2, r3);  // y2 y3 0 0
  x = _mm256_permute2f128_pd(t0, t2, 0x20);
  y = _mm256_permute2f128_pd(t1, t3, 0x20);
  z = _mm256_permute2f128_pd(t0, t2, 0x31);
}

// Columns (x of four elements, y, z) to rows (x, y, z, 0), one per element.
__attribute__((target("avx2,fma"), always_inline)) inline void transposeToRows(__m256d x, __m256d y, __m256d z,
                                                                              __m256d r[4]) {
  const __m256d zero = _mm256_setzero_pd();
  const __m256d t0 = _mm256_unpacklo_pd(x, y);     // x0 y0 x2 y2
  const __m256d t1 = _mm256_unpackhi_pd(x, y);     // x1 y1 x3 y3
  const __m256d t2 = _mm256_unpacklo_pd(z, zero);  // z0 0 z2 0
  const __m256d t3 = _mm256_unpackhi_pd(z, zero);  // z1 0 z3 0
  r[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  r[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  r[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  r[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

// Columns of four elements into the scratch, in its precision.
__attribute__((target("avx2,fma"), always_inline)) inline void storeColumn(double* to, __m256d v) {
  _mm256_store_pd(to, v);
}
__attribute__((target("avx2,fma"), always_inline)) inline void storeColumn(float* to, __m256d v) {
  _mm_store_ps(to, _mm256_cvtpd_ps(v));
}
__attribute__((target("avx2,fma"), always_inline)) inline __m256d loadColumn(const double* from) {
  return _mm256_load_pd(from);
}
__attribute__((target("avx2,fma"), always_inline)) inline __m256d loadColumn(const float* from) {
  return _mm256_cvtps_pd(_mm_load_ps(from));
}

template <typename T>
__attribute__((target("avx2,fma"), always_inline)) inline void gatherAvx2(const TLEDElements& el, size_t base,
                                                                         const double* u,
                                                                         ChunkScratch<T>& s) {
  for (size_t e = 0; e < kChunk; e += 4) {
    __m256d node0[4];
    for (int k = 0; k < 4; ++k) node0[k] = _mm256_loadu_pd(u + size_t(el.nodeOffset[0][base + e + k]));
    for (int a = 1; a < 4; ++a) {
      __m256d d[4];
      for (int k = 0; k < 4; ++k)
        d[k] = _mm256_sub_pd(_mm256_loadu_pd(u + size_t(el.nodeOffset[a][base + e + k])), node0[k]);
      __m256d x, y, z;
      transposeToColumns(d[0], d[1], d[2], d[3], x, y, z);
      storeColumn(&s.d[3 * (a - 1)][e], x);
      storeColumn(&s.d[3 * (a - 1) + 1][e], y);
      storeColumn(&s.d[3 * (a - 1) + 2][e], z);
    }
  }
}

template <typename T>
__attribute__((target("avx2,fma"), always_inline)) inline void scatterAvx2(const TLEDElements& el, size_t base,
                                                                          const ChunkScratch<T>& s,
                                                                          double* f) {
  for (size_t g = 0; g < kChunk / 4; ++g) {
    const size_t e = 4 * scatterGroup(g);
    __m256d rows[3][4];  // per local node 1..3, per element
    __m256d sum[4] = {_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd()};
    for (int a = 0; a < 3; ++a) {
      transposeToRows(loadColumn(&s.f[3 * a][e]), loadColumn(&s.f[3 * a + 1][e]), loadColumn(&s.f[3 * a + 2][e]),
                      rows[a]);
      for (int k = 0; k < 4; ++k) sum[k] = _mm256_add_pd(sum[k], rows[a][k]);
    }
    // One element after the other: elements of a chunk share nodes.
    for (int k = 0; k < 4; ++k) {
      double* f0 = f + size_t(el.nodeOffset[0][base + e + k]);
      _mm256_storeu_pd(f0, _mm256_sub_pd(_mm256_loadu_pd(f0), sum[k]));
      for (int a = 0; a < 3; ++a) {
        double* fa = f + size_t(el.nodeOffset[a + 1][base + e + k]);
        _mm256_storeu_pd(fa, _mm256_add_pd(_mm256_loadu_pd(fa), rows[a][k]));
      }
    }
  }
}

template <typename T>
__attribute__((target("avx2,fma"))) ElementStepCounts forcesAvx2(const TLEDElements& el, const double* u, double* f) {
  ElementStepCounts counts;
  ChunkScratch<T> s;
  const ElementArrays<T> arrays(el);
  for (size_t base = 0; base < el.padded; base += kChunk) {
    gatherAvx2(el, base, u, s);
    forcesOfGatheredChunk(arrays, base, s, counts);
    scatterAvx2(el, base, s, f);
  }
  return counts;
}

// Two nodes' (x, y, z, 0), one per 256-bit half.
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"), always_inline)) inline __m512d loadNodePair(
    const double* u, int32_t first, int32_t second) {
  return _mm512_insertf64x4(_mm512_broadcast_f64x4(_mm256_loadu_pd(u + first)), _mm256_loadu_pd(u + second), 1);
}
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"), always_inline)) inline void storeColumn8(double* to,
                                                                                                    __m512d v) {
  _mm512_store_pd(to, v);
}
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"), always_inline)) inline void storeColumn8(float* to,
                                                                                                    __m512d v) {
  _mm256_store_ps(to, _mm512_cvtpd_ps(v));
}

// The gather eight elements at a time: node pairs in 512-bit registers, and
// the columns from two unpacks and three two-source permutes (the AVX2 gather
// needs seven shuffles for four elements).
template <typename T>
__attribute__((target("avx512f,avx512vl,avx512dq,avx2,fma"), always_inline)) inline void gatherAvx512(
    const TLEDElements& el, size_t base, const double* u, ChunkScratch<T>& s) {
  const int32_t* offset[4];
  for (int a = 0; a < 4; ++a) offset[a] = el.nodeOffset[a].data() + base;
  // Element order within the unpacked pairs: lanes (0, 2 | 1, 3) of each 128-bit half.
  const __m512i even = _mm512_setr_epi64(0, 4, 1, 5, 8, 12, 9, 13);
  const __m512i odd = _mm512_setr_epi64(2, 6, 3, 7, 10, 14, 11, 15);
  for (size_t e = 0; e < kChunk; e += 8) {
    __m512d node0[4];
    for (int p = 0; p < 4; ++p) node0[p] = loadNodePair(u, offset[0][e + 2 * p], offset[0][e + 2 * p + 1]);
    for (int a = 1; a < 4; ++a) {
      __m512d d[4];
      for (int p = 0; p < 4; ++p)
        d[p] = _mm512_sub_pd(loadNodePair(u, offset[a][e + 2 * p], offset[a][e + 2 * p + 1]), node0[p]);
      const __m512d t0 = _mm512_unpacklo_pd(d[0], d[1]);  // x0 x2 | z0 z2 | x1 x3 | z1 z3
      const __m512d t1 = _mm512_unpackhi_pd(d[0], d[1]);  // y0 y2 | 0 0 | y1 y3 | 0 0
      const __m512d t2 = _mm512_unpacklo_pd(d[2], d[3]);  // the same for elements 4..7
      const __m512d t3 = _mm512_unpackhi_pd(d[2], d[3]);
      storeColumn8(&s.d[3 * (a - 1)][e], _mm512_permutex2var_pd(t0, even, t2));
      storeColumn8(&s.d[3 * (a - 1) + 1][e], _mm512_permutex2var_pd(t1, even, t3));
      storeColumn8(&s.d[3 * (a - 1) + 2][e], _mm512_permutex2var_pd(t0, odd, t2));
    }
  }
}

// GCC also takes the preferred vector width as a target (its loops would
// otherwise stay at 256 bits); clang does not, and drops the whole attribute.
#if defined(__clang__)
#define TREPHINE_AVX512_LOOP_TARGET "avx512f,avx512vl,avx512dq,avx2,fma"
#else
#define TREPHINE_AVX512_LOOP_TARGET "avx512f,avx512vl,avx512dq,avx2,fma,prefer-vector-width=512"
#endif

// The same loop with the gather and the arithmetic on 512-bit vectors (16
// floats or 8 doubles); the scatter as in AVX2.
template <typename T>
__attribute__((target(TREPHINE_AVX512_LOOP_TARGET))) ElementStepCounts
forcesAvx512(const TLEDElements& el, const double* u, double* f) {
  ElementStepCounts counts;
  ChunkScratch<T> s;
  const ElementArrays<T> arrays(el);
  for (size_t base = 0; base < el.padded; base += kChunk) {
    gatherAvx512(el, base, u, s);
    forcesOfGatheredChunk(arrays, base, s, counts);
    scatterAvx2(el, base, s, f);
  }
  return counts;
}

#endif

using ForcesFunction = ElementStepCounts (*)(const TLEDElements&, const double*, double*);

bool processorHas(ElementLoopIsa isa) {
#ifdef TREPHINE_TLED_AVX2
  __builtin_cpu_init();  // this may run before libgcc's own initialiser
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  switch (isa) {
    case ElementLoopIsa::kPortable:
      return true;
    case ElementLoopIsa::kAvx2:
      return avx2;
    case ElementLoopIsa::kAvx512:
      return avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
             __builtin_cpu_supports("avx512dq");
  }
  return false;
#else
  return isa == ElementLoopIsa::kPortable;
#endif
}

template <typename T>
ForcesFunction forcesFor(ElementLoopIsa isa) {
#ifdef TREPHINE_TLED_AVX2
  if (isa == ElementLoopIsa::kAvx512) return forcesAvx512<T>;
  if (isa == ElementLoopIsa::kAvx2) return forcesAvx2<T>;
#endif
  (void)isa;
  return forcesBaseline<T>;
}

}  // namespace

bool elementLoopAvailable(ElementLoopIsa isa) { return processorHas(isa); }

ElementLoopIsa bestElementLoopIsa() {
  for (ElementLoopIsa isa : {ElementLoopIsa::kAvx512, ElementLoopIsa::kAvx2})
    if (processorHas(isa)) return isa;
  return ElementLoopIsa::kPortable;
}

const char* elementLoopName(ElementLoopIsa isa) {
  switch (isa) {
    case ElementLoopIsa::kPortable:
      return "portable";
    case ElementLoopIsa::kAvx2:
      return "AVX2";
    case ElementLoopIsa::kAvx512:
      return "AVX-512";
  }
  return "?";
}

ElementStepCounts accumulateInternalForces(const TLEDElements& elements, const double* u, double* f,
                                           ElementLoopIsa isa) {
  return elements.precision == ElementPrecision::kSingle ? forcesFor<float>(isa)(elements, u, f)
                                                         : forcesFor<double>(isa)(elements, u, f);
}

}  // namespace trephine::fem
