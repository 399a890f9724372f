#include "plugins/voxel_skull/ShellPointTest.h"

#include <algorithm>

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

// Smooth surface: the trilinear density at each point against the isovalue.
[[gnu::always_inline]] inline void testPointsSmooth(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                                    PointTestOutput out) {
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  for (size_t i = 0; i < shell.size(); ++i) {
    const Vec3 p = R * Vec3(shell.x[i], shell.y[i], shell.z[i]) + X_WT.position;
    out.solid[i] = grid.codeAt(p) > grid.isoCode;
    out.voxel[i] = grid.voxelOf(p);
  }
}

}  // namespace

void testShellPointsSmoothBaseline(const SolidGrid& grid, const ShellArrays& shell, const Pose& X_WT,
                                   PointTestOutput out) {
  testPointsSmooth(grid, shell, X_WT, out);
}

#ifdef TREPHINE_HAS_AVX2_PATH
__attribute__((target("avx2"))) void testShellPointsSmoothAvx2(const SolidGrid& grid, const ShellArrays& shell,
                                                               const Pose& X_WT, PointTestOutput out) {
  testPointsSmooth(grid, shell, X_WT, out);
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
#ifdef TREPHINE_HAS_AVX2_PATH
  if (hasAvx2()) return smooth ? &testShellPointsSmoothAvx2 : &testShellPointsAvx2;
#endif
  return smooth ? &testShellPointsSmoothBaseline : &testShellPointsBaseline;
}

const char* bestShellPointTestName() { return hasAvx2() ? "avx2" : "sse2"; }

}  // namespace trephine::voxel
