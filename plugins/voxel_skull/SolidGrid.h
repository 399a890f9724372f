#pragma once
// The hot-loop view of a density volume: which voxel a point falls in and
// whether that voxel is solid (density above the isovalue). Plain data and
// inline functions, no allocation.
#include <cmath>
#include <cstdint>

#include "plugins/voxel_skull/DensityVolume.h"

namespace trephine::voxel {

struct SolidGrid {
  VoxelCode* codes = nullptr;
  int32_t nx = 0, ny = 0, nz = 0;
  Vec3 corner = Vec3::Zero();  // mm, outer corner of voxel (0, 0, 0)
  Vec3 spacing = Vec3::Ones();  // mm
  Vec3 inverseSpacing = Vec3::Ones();  // 1/mm
  int32_t threshold = 0;  // codes >= threshold are solid

  static SolidGrid of(DensityVolume& volume, double isovalue) {
    SolidGrid g;
    g.codes = volume.codes();
    g.nx = volume.dims()[0];
    g.ny = volume.dims()[1];
    g.nz = volume.dims()[2];
    g.spacing = volume.spacing();
    g.corner = volume.origin() - 0.5 * g.spacing;
    g.inverseSpacing = g.spacing.cwiseInverse();
    g.threshold = volume.encoding().thresholdCode(isovalue);
    return g;
  }

  bool inside(int64_t i, int64_t j, int64_t k) const {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz;
  }
  int64_t linear(int64_t i, int64_t j, int64_t k) const { return i + int64_t(nx) * (j + int64_t(ny) * k); }
  bool solidCell(int64_t i, int64_t j, int64_t k) const {
    return inside(i, j, k) && codes[linear(i, j, k)] >= threshold;
  }
  // Voxel of a world point, or -1 outside the grid (also for NaN).
  int64_t voxelOf(const Vec3& p) const {
    const double gx = (p.x() - corner.x()) * inverseSpacing.x();
    const double gy = (p.y() - corner.y()) * inverseSpacing.y();
    const double gz = (p.z() - corner.z()) * inverseSpacing.z();
    if (!(gx >= 0 && gy >= 0 && gz >= 0 && gx < nx && gy < ny && gz < nz)) return -1;
    return linear(int64_t(gx), int64_t(gy), int64_t(gz));
  }
  bool solidAt(const Vec3& p) const {
    const int64_t v = voxelOf(p);
    return v >= 0 && codes[v] >= threshold;
  }
  Vec3 centerOf(int64_t linearIndex) const {
    const int64_t i = linearIndex % nx, j = (linearIndex / nx) % ny, k = linearIndex / (int64_t(nx) * ny);
    return corner + Vec3((i + 0.5) * spacing.x(), (j + 0.5) * spacing.y(), (k + 0.5) * spacing.z());
  }
  double smallestSide() const { return spacing.minCoeff(); }
};

}  // namespace trephine::voxel
