#pragma once
// Checks a volume resampled from an oblique or sheared stored grid against a
// density that is linear in the stored index (which trilinear interpolation
// reproduces exactly): inside the stored samples' hull each voxel holds that
// density to within code rounding; beyond half a voxel outside, the lowest.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <array>
#include <functional>

#include "framework/data/DensityVolume.h"

namespace trephine::test {

// Returns the number of voxels found inside the hull (so a caller can
// require that the check saw the volume).
inline size_t expectResampledLinear(const DensityVolume& volume, const std::array<int64_t, 3>& storedDims,
                                    const Eigen::Matrix3d& axes, const Vec3& storedOrigin,
                                    const std::function<double(const Vec3&)>& densityAtIndex, double air) {
  const Eigen::Matrix3d toIndex = axes.inverse();
  // Code rounding, and the float precision of the geometry some headers store.
  const double rounding = 0.5 * volume.encoding().scale + 1e-3;
  size_t inside = 0;
  for (int32_t k = 0; k < volume.dims()[2]; ++k)
    for (int32_t j = 0; j < volume.dims()[1]; ++j)
      for (int32_t i = 0; i < volume.dims()[0]; ++i) {
        const Vec3 world = volume.origin() + Vec3(i, j, k).cwiseProduct(volume.spacing());
        const Vec3 u = toIndex * (world - storedOrigin);
        bool within = true, beyond = false;
        for (int a = 0; a < 3; ++a) {
          within = within && u[a] >= -1e-9 && u[a] <= double(storedDims[a] - 1) + 1e-9;
          beyond = beyond || u[a] < -0.5 - 1e-6 || u[a] > double(storedDims[a] - 1) + 0.5 + 1e-6;
        }
        if (within) {
          ++inside;
          EXPECT_NEAR(volume.density(i, j, k), densityAtIndex(u), rounding) << "voxel " << i << " " << j << " " << k;
        } else if (beyond) {
          EXPECT_EQ(volume.density(i, j, k), air) << "voxel " << i << " " << j << " " << k;
        }
      }
  return inside;
}

}  // namespace trephine::test
