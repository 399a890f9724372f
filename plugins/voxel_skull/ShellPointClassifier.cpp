#include "plugins/voxel_skull/ShellPointClassifier.h"

#include <algorithm>
#include <cstring>
#ifdef TREPHINE_HAS_AVX2_PATH
#include <immintrin.h>
#endif

namespace trephine::voxel {

void ShellArrays::assign(std::span<const ShellPoint> shell) {
  x.resize(shell.size());
  y.resize(shell.size());
  z.resize(shell.size());
  for (size_t i = 0; i < shell.size(); ++i) {
    x[i] = shell[i].position.x();
    y[i] = shell[i].position.y();
    z[i] = shell[i].position.z();
  }
}

namespace {

[[gnu::always_inline]] inline void testPoints(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                              PointTestOutput out) {
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  // Grid coordinates g = (R p + t - corner) / spacing, folded into one affine map.
  double m[3][3], c[3];
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) m[r][k] = R(r, k) * grid.inverseSpacing[r];
    c[r] = (X_WT.position[r] - grid.corner[r]) * grid.inverseSpacing[r];
  }
  const double nx = grid.nx, ny = grid.ny, nz = grid.nz;
  // 32-bit indices: volumes hold fewer than 2^31 voxels, and 32-bit conversions
  // vectorise (SSE2 cvttpd2dq) where 64-bit ones need AVX-512.
  const int32_t strideY = grid.nx, strideZ = grid.nx * grid.ny;
  const double* __restrict px = shell.x.data();
  const double* __restrict py = shell.y.data();
  const double* __restrict pz = shell.z.data();
  const size_t n = shell.size();
  constexpr size_t kChunk = 64;
  alignas(64) int32_t index[kChunk];
  const VoxelCode* __restrict codes = grid.codes;
  const int32_t threshold = grid.threshold;
  for (size_t start = 0; start < n; start += kChunk) {
    const size_t count = std::min(kChunk, n - start);
    for (size_t i = 0; i < count; ++i) {
      const size_t k = start + i;
      const double gx = m[0][0] * px[k] + m[0][1] * py[k] + m[0][2] * pz[k] + c[0];
      const double gy = m[1][0] * px[k] + m[1][1] * py[k] + m[1][2] * pz[k] + c[1];
      const double gz = m[2][0] * px[k] + m[2][1] * py[k] + m[2][2] * pz[k] + c[2];
      // Non-short-circuit tests and selects keep the loop free of branches (vectorisable).
      const bool inside = (gx >= 0) & (gy >= 0) & (gz >= 0) & (gx < nx) & (gy < ny) & (gz < nz);
      // Truncation is floor here: negative coordinates are outside anyway.
      const int32_t linear =
          int32_t(inside ? gx : 0.0) + strideY * int32_t(inside ? gy : 0.0) + strideZ * int32_t(inside ? gz : 0.0);
      index[i] = inside ? linear : -1;
    }
    for (size_t i = 0; i < count; ++i) {
      const int32_t v = index[i];
      out.voxel[start + i] = v;
      out.solid[start + i] = v >= 0 && codes[v >= 0 ? v : 0] >= threshold;
    }
  }
}

// Smooth surface, the reference: the trilinear density at each point against the isovalue.
[[gnu::always_inline]] inline void testPointsSmooth(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                                    PointTestOutput out) {
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  for (size_t i = 0; i < shell.size(); ++i) {
    const Vec3 p = R * Vec3(shell.x[i], shell.y[i], shell.z[i]) + X_WT.position;
    out.solid[i] = grid.codeAt(p) > grid.isoCode;
    out.voxel[i] = grid.voxelOf(p);
  }
}

// What the fast smooth test needs of the grid and the pose, read once a call,
// and its queue of points to interpolate.
struct SmoothSetup {
  double r00, r01, r02, r10, r11, r12, r20, r21, r22, t0, t1, t2;  // rotation and translation
  double cx, cy, cz, sx, sy, sz;                                    // grid corner and inverse spacing
  double dnx, dny, dnz;                                             // grid size as doubles
  int32_t nx, ny, nz, strideY, strideZ;                             // voxels
  int32_t cellY, cellZ;                                             // padded occupancy cells
  const uint8_t* states;                                            // occupancy cells, or null
  bool outsideSolid;                                                // outsideCode > isoCode
};

// Points inside the grid (all 8 corners voxels) in a cell the surface may
// cross, queued to interpolate.
constexpr size_t kPendingCapacity = 64;
struct PendingPoints {
  alignas(32) int32_t point[kPendingCapacity];  // index in the shell
  alignas(32) int32_t base[kPendingCapacity];   // linear index of the cell's corner (i, j, k)
  alignas(32) double tx[kPendingCapacity], ty[kPendingCapacity], tz[kPendingCapacity];  // weights
  size_t count = 0;
};

// solid[point] = trilinear code > isoCode for pending points [from, count), in
// exactly the operations and order of SolidGrid::codeAt.
[[gnu::always_inline]] inline void interpolatePending(const SolidGrid& grid, const PendingPoints& pending, size_t from,
                                                      uint8_t* solid) {
  const VoxelCode* codes = grid.codes;
  const int64_t sy = grid.nx, sz = int64_t(grid.nx) * grid.ny;
  const double iso = grid.isoCode;
  for (size_t q = from; q < pending.count; ++q) {
    const VoxelCode* b = codes + pending.base[q];
    const double tx = pending.tx[q], ty = pending.ty[q], tz = pending.tz[q];
    const double c000 = b[0], c100 = b[1], c010 = b[sy], c110 = b[sy + 1];
    const double c001 = b[sz], c101 = b[sz + 1], c011 = b[sz + sy], c111 = b[sz + sy + 1];
    const double c00 = c000 + tx * (c100 - c000);
    const double c10 = c010 + tx * (c110 - c010);
    const double c01 = c001 + tx * (c101 - c001);
    const double c11 = c011 + tx * (c111 - c011);
    const double c0 = c00 + ty * (c10 - c00), c1 = c01 + ty * (c11 - c01);
    solid[pending.point[q]] = c0 + tz * (c1 - c0) > iso;
  }
}

using InterpolateFunction = void (*)(const SolidGrid& grid, const PendingPoints& pending, uint8_t* solid);

void interpolatePendingBaseline(const SolidGrid& grid, const PendingPoints& pending, uint8_t* solid) {
  interpolatePending(grid, pending, 0, solid);
}

// One point: the world point as Eigen's R * p + t computes it (see
// transformMatchesEigen), SolidGrid::voxelOf, then codeAt's cases: beyond its
// range (1.5 voxels out of the grid's outer centres) outsideCode, or NaN for NaN
// coordinates; a decided occupancy cell; a cell inside the grid is queued; a
// cell on the grid's faces (outer corners outsideCode) goes through codeAt.
template <InterpolateFunction interpolate>
[[gnu::always_inline]] inline void testSmoothPoint(const SmoothSetup& s, const SolidGrid& grid,
                                                   const ShellArrays& shell, size_t k, PendingPoints& pending,
                                                   PointTestOutput out) {
  const double px = shell.x[k], py = shell.y[k], pz = shell.z[k];
  const double x = s.r00 * px + s.r01 * py + s.r02 * pz + s.t0;
  const double y = s.r10 * px + s.r11 * py + s.r12 * pz + s.t1;
  const double z = s.r20 * px + (s.r21 * py + s.r22 * pz) + s.t2;
  const double gx = (x - s.cx) * s.sx, gy = (y - s.cy) * s.sy, gz = (z - s.cz) * s.sz;
  const bool inside = gx >= 0 && gy >= 0 && gz >= 0 && gx < s.dnx && gy < s.dny && gz < s.dnz;
  out.voxel[k] = inside ? int32_t(gx) + s.strideY * int32_t(gy) + s.strideZ * int32_t(gz) : -1;
  const double ux = gx - 0.5, uy = gy - 0.5, uz = gz - 0.5;
  if (!(ux > -2 && uy > -2 && uz > -2 && ux < s.dnx + 1 && uy < s.dny + 1 && uz < s.dnz + 1)) {
    out.solid[k] = ux == ux && uy == uy && uz == uz && s.outsideSolid;
    return;
  }
  // Floor by truncation, one down below a negative non-integer (exact in range).
  const int32_t ti = int32_t(ux), tj = int32_t(uy), tk = int32_t(uz);
  const int32_t i = ti - (double(ti) > ux), j = tj - (double(tj) > uy), l = tk - (double(tk) > uz);
  if (s.states) {
    const int32_t cell = (i + 2) + s.cellY * (j + 2) + s.cellZ * (l + 2);
    const int state = (s.states[cell >> 2] >> ((cell & 3) * 2)) & 3;
    if (state & 1) {
      out.solid[k] = state >> 1;
      return;
    }
  }
  if (i >= 0 && j >= 0 && l >= 0 && i < s.nx - 1 && j < s.ny - 1 && l < s.nz - 1) {
    if (pending.count == kPendingCapacity) {
      interpolate(grid, pending, out.solid);
      pending.count = 0;
    }
    const size_t q = pending.count++;
    pending.point[q] = int32_t(k);
    pending.base[q] = i + s.strideY * j + s.strideZ * l;
    pending.tx[q] = ux - double(i), pending.ty[q] = uy - double(j), pending.tz[q] = uz - double(l);
  } else {
    out.solid[k] = grid.codeAt(Vec3(x, y, z)) > grid.isoCode;
  }
}

using SmoothPointsFunction = void (*)(const SmoothSetup& s, const SolidGrid& grid, const ShellArrays& shell,
                                      PendingPoints& pending, PointTestOutput out);

void testSmoothPointsBaseline(const SmoothSetup& s, const SolidGrid& grid, const ShellArrays& shell,
                              PendingPoints& pending, PointTestOutput out) {
  for (size_t k = 0; k < shell.size(); ++k)
    testSmoothPoint<interpolatePendingBaseline>(s, grid, shell, k, pending, out);
}

#ifdef TREPHINE_HAS_AVX2_PATH
// The lower and the upper int16 of each 32-bit lane, as doubles.
__attribute__((target("avx2"), always_inline)) inline __m256d lowCodes(__m128i pair) {
  return _mm256_cvtepi32_pd(_mm_srai_epi32(_mm_slli_epi32(pair, 16), 16));
}
__attribute__((target("avx2"), always_inline)) inline __m256d highCodes(__m128i pair) {
  return _mm256_cvtepi32_pd(_mm_srai_epi32(pair, 16));
}
// a + t (b - a)
__attribute__((target("avx2"), always_inline)) inline __m256d lerp(__m256d a, __m256d b, __m256d t) {
  return _mm256_add_pd(a, _mm256_mul_pd(t, _mm256_sub_pd(b, a)));
}

// 4 points at a time: the codes of a cell come as 4 pairs of x neighbours,
// each pair one 32-bit gather lane (low half the lower x; both are voxels, as
// the cell is inside the grid); then codeAt's arithmetic in lanes (no FMA: every
// product and sum rounds as in the scalar code).
__attribute__((target("avx2"))) void interpolatePendingAvx2(const SolidGrid& grid, const PendingPoints& pending,
                                                            uint8_t* solid) {
  const int* codes = reinterpret_cast<const int*>(grid.codes);
  const __m128i sy = _mm_set1_epi32(grid.nx), sz = _mm_set1_epi32(grid.nx * grid.ny);
  const __m256d iso = _mm256_set1_pd(grid.isoCode);
  size_t q = 0;
  for (; q + 4 <= pending.count; q += 4) {
    const __m128i base = _mm_load_si128(reinterpret_cast<const __m128i*>(pending.base + q));
    const __m128i baseY = _mm_add_epi32(base, sy), baseZ = _mm_add_epi32(base, sz);
    const __m128i p00 = _mm_i32gather_epi32(codes, base, 2);                      // (0, 0, 0), (1, 0, 0)
    const __m128i p10 = _mm_i32gather_epi32(codes, baseY, 2);                     // (0, 1, 0), (1, 1, 0)
    const __m128i p01 = _mm_i32gather_epi32(codes, baseZ, 2);                     // (0, 0, 1), (1, 0, 1)
    const __m128i p11 = _mm_i32gather_epi32(codes, _mm_add_epi32(baseZ, sy), 2);  // (0, 1, 1), (1, 1, 1)
    const __m256d tx = _mm256_load_pd(pending.tx + q), ty = _mm256_load_pd(pending.ty + q);
    const __m256d tz = _mm256_load_pd(pending.tz + q);
    const __m256d c00 = lerp(lowCodes(p00), highCodes(p00), tx), c10 = lerp(lowCodes(p10), highCodes(p10), tx);
    const __m256d c01 = lerp(lowCodes(p01), highCodes(p01), tx), c11 = lerp(lowCodes(p11), highCodes(p11), tx);
    const __m256d c0 = lerp(c00, c10, ty), c1 = lerp(c01, c11, ty);
    const int above = _mm256_movemask_pd(_mm256_cmp_pd(lerp(c0, c1, tz), iso, _CMP_GT_OQ));
    for (int lane = 0; lane < 4; ++lane) solid[pending.point[q + lane]] = (above >> lane) & 1;
  }
  interpolatePending(grid, pending, q, solid);
}

// 64-bit lane masks of 4 doubles as 32-bit lane masks.
__attribute__((target("avx2"), always_inline)) inline __m128i narrowMask(__m256d mask) {
  const __m256i even = _mm256_permutevar8x32_epi32(_mm256_castpd_si256(mask), _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7));
  return _mm256_castsi256_si128(even);
}
__attribute__((target("avx2"), always_inline)) inline __m256d and3(__m256d a, __m256d b, __m256d c) {
  return _mm256_and_pd(_mm256_and_pd(a, b), c);
}

// testSmoothPoint 4 points at a time, in lanes with the same operations (the
// voxel, base and cell indices are exact integers in doubles); the cell
// states come in one gather; the points left undecided (a tenth or less)
// are queued or go through codeAt one by one; the last n mod 4 points go
// through testSmoothPoint.
__attribute__((target("avx2"))) void testSmoothPointsAvx2(const SmoothSetup& s, const SolidGrid& grid,
                                                          const ShellArrays& shell, PendingPoints& pending,
                                                          PointTestOutput out) {
  const __m256d r00 = _mm256_set1_pd(s.r00), r01 = _mm256_set1_pd(s.r01), r02 = _mm256_set1_pd(s.r02);
  const __m256d r10 = _mm256_set1_pd(s.r10), r11 = _mm256_set1_pd(s.r11), r12 = _mm256_set1_pd(s.r12);
  const __m256d r20 = _mm256_set1_pd(s.r20), r21 = _mm256_set1_pd(s.r21), r22 = _mm256_set1_pd(s.r22);
  const __m256d t0 = _mm256_set1_pd(s.t0), t1 = _mm256_set1_pd(s.t1), t2 = _mm256_set1_pd(s.t2);
  const __m256d cx = _mm256_set1_pd(s.cx), cy = _mm256_set1_pd(s.cy), cz = _mm256_set1_pd(s.cz);
  const __m256d sx = _mm256_set1_pd(s.sx), sy = _mm256_set1_pd(s.sy), sz = _mm256_set1_pd(s.sz);
  const __m256d dnx = _mm256_set1_pd(s.dnx), dny = _mm256_set1_pd(s.dny), dnz = _mm256_set1_pd(s.dnz);
  const __m256d hix = _mm256_set1_pd(s.dnx + 1), hiy = _mm256_set1_pd(s.dny + 1), hiz = _mm256_set1_pd(s.dnz + 1);
  const __m256d lastX = _mm256_set1_pd(s.dnx - 1), lastY = _mm256_set1_pd(s.dny - 1), lastZ = _mm256_set1_pd(s.dnz - 1);
  const __m256d zero = _mm256_setzero_pd(), half = _mm256_set1_pd(0.5);
  const __m256d cellOrigin = _mm256_set1_pd(2.0 + 2.0 * s.cellY + 2.0 * s.cellZ);
  const __m256d minus1 = _mm256_set1_pd(-1.0), minus2 = _mm256_set1_pd(-2.0);
  const __m256d strideY = _mm256_set1_pd(s.strideY), strideZ = _mm256_set1_pd(s.strideZ);
  const __m256d cellY = _mm256_set1_pd(s.cellY), cellZ = _mm256_set1_pd(s.cellZ);
  const __m128i three = _mm_set1_epi32(3), one = _mm_set1_epi32(1), zero32 = _mm_setzero_si128();
  const __m128i two32 = _mm_set1_epi32(2);
  const int* states = reinterpret_cast<const int*>(s.states);
  const size_t n = shell.size();
  size_t k = 0;
  for (; k + 4 <= n; k += 4) {
    const __m256d X = _mm256_loadu_pd(shell.x.data() + k), Y = _mm256_loadu_pd(shell.y.data() + k);
    const __m256d Z = _mm256_loadu_pd(shell.z.data() + k);
    const __m256d x = _mm256_add_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(r00, X), _mm256_mul_pd(r01, Y)), _mm256_mul_pd(r02, Z)), t0);
    const __m256d y = _mm256_add_pd(
        _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(r10, X), _mm256_mul_pd(r11, Y)), _mm256_mul_pd(r12, Z)), t1);
    const __m256d z = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(r20, X), _mm256_add_pd(_mm256_mul_pd(r21, Y), _mm256_mul_pd(r22, Z))), t2);
    const __m256d gx = _mm256_mul_pd(_mm256_sub_pd(x, cx), sx);
    const __m256d gy = _mm256_mul_pd(_mm256_sub_pd(y, cy), sy);
    const __m256d gz = _mm256_mul_pd(_mm256_sub_pd(z, cz), sz);
    // codeAt: its range, floor and weights, the cell and its state.
    const __m256d ux = _mm256_sub_pd(gx, half), uy = _mm256_sub_pd(gy, half), uz = _mm256_sub_pd(gz, half);
    const __m256d near = _mm256_and_pd(
        and3(_mm256_cmp_pd(ux, minus2, _CMP_GT_OQ), _mm256_cmp_pd(uy, minus2, _CMP_GT_OQ),
             _mm256_cmp_pd(uz, minus2, _CMP_GT_OQ)),
        and3(_mm256_cmp_pd(ux, hix, _CMP_LT_OQ), _mm256_cmp_pd(uy, hiy, _CMP_LT_OQ), _mm256_cmp_pd(uz, hiz, _CMP_LT_OQ)));
    // Beyond the range: state "decided", solid when outsideCode is and no coordinate is NaN.
    __m128i state = one;
    if (s.outsideSolid)
      state = _mm_or_si128(one, _mm_and_si128(two32, narrowMask(and3(_mm256_cmp_pd(ux, ux, _CMP_ORD_Q),
                                                                     _mm256_cmp_pd(uy, uy, _CMP_ORD_Q),
                                                                     _mm256_cmp_pd(uz, uz, _CMP_ORD_Q)))));
    if (_mm256_movemask_pd(near) == 0) {  // 4 points beyond the range (common above a skull's top)
      const __m128i solid = _mm_srli_epi32(state, 1);
      const int solidBytes = _mm_cvtsi128_si32(_mm_packus_epi16(_mm_packs_epi32(solid, solid), zero32));
      std::memcpy(out.solid + k, &solidBytes, 4);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.voxel + k), _mm256_set1_epi64x(-1));  // not in the grid
      continue;
    }
    // voxelOf (ordered comparisons: false for NaN); truncation is floor on inside lanes.
    const __m256d inside = _mm256_and_pd(
        and3(_mm256_cmp_pd(gx, zero, _CMP_GE_OQ), _mm256_cmp_pd(gy, zero, _CMP_GE_OQ),
             _mm256_cmp_pd(gz, zero, _CMP_GE_OQ)),
        and3(_mm256_cmp_pd(gx, dnx, _CMP_LT_OQ), _mm256_cmp_pd(gy, dny, _CMP_LT_OQ), _mm256_cmp_pd(gz, dnz, _CMP_LT_OQ)));
    const __m256d vx = _mm256_round_pd(_mm256_and_pd(inside, gx), _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
    const __m256d vy = _mm256_round_pd(_mm256_and_pd(inside, gy), _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
    const __m256d vz = _mm256_round_pd(_mm256_and_pd(inside, gz), _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
    const __m256d voxel = _mm256_add_pd(vx, _mm256_add_pd(_mm256_mul_pd(strideY, vy), _mm256_mul_pd(strideZ, vz)));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out.voxel + k),
                        _mm256_cvtepi32_epi64(_mm256_cvttpd_epi32(_mm256_blendv_pd(minus1, voxel, inside))));
    // Floors and cells are garbage beyond the range (NaN, huge): those lanes are masked.
    const __m256d fx = _mm256_floor_pd(ux), fy = _mm256_floor_pd(uy), fz = _mm256_floor_pd(uz);
    const __m128i near32 = narrowMask(near);
    __m128i nearState = zero32;  // surface: interpolate
    if (states) {
      // (i + 2) + cellY (j + 2) + cellZ (k + 2), exact in doubles
      const __m256d cell =
          _mm256_add_pd(_mm256_add_pd(fx, cellOrigin), _mm256_add_pd(_mm256_mul_pd(cellY, fy), _mm256_mul_pd(cellZ, fz)));
      const __m128i cell32 = _mm256_cvttpd_epi32(cell);
      const __m128i word = _mm_mask_i32gather_epi32(zero32, states, _mm_srli_epi32(cell32, 2), near32, 1);
      nearState = _mm_and_si128(_mm_srlv_epi32(word, _mm_slli_epi32(_mm_and_si128(cell32, three), 1)), three);
    }
    state = _mm_blendv_epi8(state, nearState, near32);
    const __m128i solid = _mm_srli_epi32(state, 1);
    const int solidBytes = _mm_cvtsi128_si32(_mm_packus_epi16(_mm_packs_epi32(solid, solid), zero32));
    std::memcpy(out.solid + k, &solidBytes, 4);
    const int undecided = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(state, one), zero32)));
    if (undecided == 0) continue;
    // The surface's points: interpolate inside the grid, codeAt on its faces.
    const __m256d interior = _mm256_and_pd(
        and3(near, _mm256_cmp_pd(fx, zero, _CMP_GE_OQ), _mm256_cmp_pd(fy, zero, _CMP_GE_OQ)),
        _mm256_and_pd(_mm256_cmp_pd(fz, zero, _CMP_GE_OQ),
                      and3(_mm256_cmp_pd(fx, lastX, _CMP_LT_OQ), _mm256_cmp_pd(fy, lastY, _CMP_LT_OQ),
                           _mm256_cmp_pd(fz, lastZ, _CMP_LT_OQ))));
    const int interiorLanes = _mm256_movemask_pd(interior);
    alignas(32) double lane[6][4];
    alignas(16) int32_t base[4];
    _mm256_store_pd(lane[0], _mm256_sub_pd(ux, fx));
    _mm256_store_pd(lane[1], _mm256_sub_pd(uy, fy));
    _mm256_store_pd(lane[2], _mm256_sub_pd(uz, fz));
    _mm_store_si128(reinterpret_cast<__m128i*>(base), _mm256_cvttpd_epi32(_mm256_add_pd(
                                                          fx, _mm256_add_pd(_mm256_mul_pd(strideY, fy),
                                                                            _mm256_mul_pd(strideZ, fz)))));
    for (int b = 0; b < 4; ++b) {
      if (!((undecided >> b) & 1)) continue;
      if ((interiorLanes >> b) & 1) {
        if (pending.count == kPendingCapacity) {
          interpolatePendingAvx2(grid, pending, out.solid);
          pending.count = 0;
        }
        const size_t q = pending.count++;
        pending.point[q] = int32_t(k + b);
        pending.base[q] = base[b];
        pending.tx[q] = lane[0][b], pending.ty[q] = lane[1][b], pending.tz[q] = lane[2][b];
      } else {
        _mm256_store_pd(lane[3], x), _mm256_store_pd(lane[4], y), _mm256_store_pd(lane[5], z);
        out.solid[k + b] = grid.codeAt(Vec3(lane[3][b], lane[4][b], lane[5][b])) > grid.isoCode;
      }
    }
  }
  for (; k < n; ++k) testSmoothPoint<interpolatePendingAvx2>(s, grid, shell, k, pending, out);
}
#endif

// Whether the fast smooth test reproduces `R * v + t` of Eigen bit for bit: rows
// 0 and 1 as (r0 x + r1 y) + r2 z, row 2 as r0 x + (r1 y + r2 z) (Eigen's
// 2-wide packets for rows 0 and 1, its pairwise reduction for the last row).
// Another Eigen or vectorisation setting may order the sums differently; then
// the reference test is used instead. Checked once, on fixed pseudo-random data.
bool transformMatchesEigen() {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto next = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(int64_t(state >> 11) - (int64_t(1) << 52)) * 0x1p-45;  // about +-128
  };
  for (int trial = 0; trial < 256; ++trial) {
    Eigen::Quaterniond q(next(), next(), next(), next());
    q.normalize();
    const Eigen::Matrix3d R = q.toRotationMatrix();
    const Vec3 v(next(), next(), next()), t(next(), next(), next());
    const Vec3 p = R * v + t;
    const double x = R(0, 0) * v.x() + R(0, 1) * v.y() + R(0, 2) * v.z() + t.x();
    const double y = R(1, 0) * v.x() + R(1, 1) * v.y() + R(1, 2) * v.z() + t.y();
    const double z = R(2, 0) * v.x() + (R(2, 1) * v.y() + R(2, 2) * v.z()) + t.z();
    if (!(x == p.x() && y == p.y() && z == p.z())) return false;
  }
  return true;
}

// The fast smooth test: `points` decides each point or queues it, `interpolate`
// does the queued ones.
template <SmoothPointsFunction points, InterpolateFunction interpolate>
[[gnu::always_inline]] inline void testPointsSmoothFast(const SolidGrid& grid, const ShellArrays& shell,
                                                        const Pose& X_WT, PointTestOutput out) {
  // 32-bit indices need the padded cell grid below 2^31 cells.
  if ((int64_t(grid.nx) + 3) * (int64_t(grid.ny) + 3) * (int64_t(grid.nz) + 3) >= (int64_t(1) << 31)) {
    testPointsSmooth(grid, shell, X_WT, out);
    return;
  }
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  SmoothSetup s;
  s.r00 = R(0, 0), s.r01 = R(0, 1), s.r02 = R(0, 2), s.t0 = X_WT.position.x();
  s.r10 = R(1, 0), s.r11 = R(1, 1), s.r12 = R(1, 2), s.t1 = X_WT.position.y();
  s.r20 = R(2, 0), s.r21 = R(2, 1), s.r22 = R(2, 2), s.t2 = X_WT.position.z();
  s.cx = grid.corner.x(), s.cy = grid.corner.y(), s.cz = grid.corner.z();
  s.sx = grid.inverseSpacing.x(), s.sy = grid.inverseSpacing.y(), s.sz = grid.inverseSpacing.z();
  s.nx = grid.nx, s.ny = grid.ny, s.nz = grid.nz;
  s.dnx = grid.nx, s.dny = grid.ny, s.dnz = grid.nz;
  s.strideY = grid.nx, s.strideZ = grid.nx * grid.ny;
  s.cellY = grid.nx + 3, s.cellZ = (grid.nx + 3) * (grid.ny + 3);
  s.states = grid.occupancy ? grid.occupancy->states() : nullptr;
  s.outsideSolid = grid.outsideCode > grid.isoCode;
  PendingPoints pending;
  points(s, grid, shell, pending, out);
  interpolate(grid, pending, out.solid);
}

}  // namespace

void testShellPointsSmoothScalar(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                 PointTestOutput out) {
  testPointsSmooth(grid, shell, X_WT, out);
}

void testShellPointsSmoothBaseline(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                   PointTestOutput out) {
  testPointsSmoothFast<testSmoothPointsBaseline, interpolatePendingBaseline>(grid, shell, X_WT, out);
}

#ifdef TREPHINE_HAS_AVX2_PATH
__attribute__((target("avx2"))) void testShellPointsSmoothAvx2(const SolidGrid& grid, const ShellArrays& shell,
                                                               const Pose& X_WT, PointTestOutput out) {
  testPointsSmoothFast<testSmoothPointsAvx2, interpolatePendingAvx2>(grid, shell, X_WT, out);
}
#endif

void testShellPointsBaseline(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT, PointTestOutput out) {
  testPoints(grid, shell, X_WT, out);
}

#ifdef TREPHINE_HAS_AVX2_PATH
__attribute__((target("avx2"))) void testShellPointsAvx2(const SolidGrid& grid, const ShellArrays& shell,
                                                         const Pose& X_WT, PointTestOutput out) {
  testPoints(grid, shell, X_WT, out);
}
#endif

namespace {
bool hasAvx2() {
#ifdef TREPHINE_HAS_AVX2_PATH
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}
}  // namespace

ShellPointTestFunction bestShellPointTest(bool smooth) {
  // The fast smooth tests assume Eigen's order of sums in R * p + t (checked once).
  static const bool fastSmooth = transformMatchesEigen();
  if (smooth && !fastSmooth) return &testShellPointsSmoothScalar;
#ifdef TREPHINE_HAS_AVX2_PATH
  if (hasAvx2()) return smooth ? &testShellPointsSmoothAvx2 : &testShellPointsAvx2;
#endif
  return smooth ? &testShellPointsSmoothBaseline : &testShellPointsBaseline;
}

const char* bestShellPointTestName() { return hasAvx2() ? "avx2" : "sse2"; }

}  // namespace trephine::voxel
