#include "framework/formats/volume/Resample.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace trephine::formats {

namespace {

constexpr double kMaxVoxels = double(uint64_t(1) << 31);

// For one axis: the lower source index and the weight of the upper one at each new voxel centre.
struct AxisSamples {
  std::vector<int64_t> lower;
  std::vector<double> upperWeight;
};

AxisSamples axisSamples(int32_t sourceCount, double sourceOrigin, double sourceSpacing, int32_t count, double origin,
                        double spacing) {
  AxisSamples samples;
  samples.lower.resize(size_t(count));
  samples.upperWeight.resize(size_t(count));
  const double last = double(sourceCount - 1);
  for (int32_t n = 0; n < count; ++n) {
    // Continuous source index of the new centre, clamped to the outermost source centres.
    const double u = std::clamp((origin + n * spacing - sourceOrigin) / sourceSpacing, 0.0, last);
    const int64_t lower = std::min<int64_t>(int64_t(std::floor(u)), std::max(0, sourceCount - 2));
    samples.lower[size_t(n)] = lower;
    samples.upperWeight[size_t(n)] = sourceCount > 1 ? u - double(lower) : 0.0;
  }
  return samples;
}

}  // namespace

DensityVolume resampleToVoxelSize(const DensityVolume& source, double voxelSizeMm) {
  if (!(voxelSizeMm > 0) || !std::isfinite(voxelSizeMm))
    throw std::invalid_argument("voxel size must be a positive number of mm, got " + std::to_string(voxelSizeMm));
  if (source.voxelCount() == 0) throw std::invalid_argument("cannot resample an empty volume");
  const std::array<int32_t, 3>& sourceDims = source.dims();
  std::array<int32_t, 3> dims{};
  Vec3 origin;
  double voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const double extent = sourceDims[a] * source.spacing()[a];
    const double count = std::max(1.0, std::round(extent / voxelSizeMm));
    voxels *= count;
    if (!(voxels <= kMaxVoxels))
      throw std::invalid_argument("resampling to " + std::to_string(voxelSizeMm) + " mm gives more than 2^31 voxels");
    dims[a] = int32_t(count);
    // Centre the new grid on the source's extent (the rounded count may not fill it exactly).
    const double centre = source.origin()[a] + 0.5 * (sourceDims[a] - 1) * source.spacing()[a];
    origin[a] = centre - 0.5 * (count - 1) * voxelSizeMm;
  }
  DensityVolume result(dims, Vec3::Constant(voxelSizeMm), origin, source.encoding());

  std::array<AxisSamples, 3> axes;
  for (int a = 0; a < 3; ++a)
    axes[a] = axisSamples(sourceDims[a], source.origin()[a], source.spacing()[a], dims[a], origin[a], voxelSizeMm);
  // Both volumes share the encoding, so interpolating codes interpolates densities.
  const VoxelCode* codes = source.codes();
  VoxelCode* out = result.codes();
  const int64_t strideJ = sourceDims[0];
  const int64_t strideK = int64_t(sourceDims[0]) * sourceDims[1];
  const int64_t stepI = sourceDims[0] > 1 ? 1 : 0;
  const int64_t stepJ = sourceDims[1] > 1 ? strideJ : 0;
  const int64_t stepK = sourceDims[2] > 1 ? strideK : 0;
  constexpr double kCodeMin = std::numeric_limits<VoxelCode>::min();
  constexpr double kCodeMax = std::numeric_limits<VoxelCode>::max();
  size_t target = 0;
  for (int32_t k = 0; k < dims[2]; ++k) {
    const double wk = axes[2].upperWeight[size_t(k)];
    const int64_t baseK = axes[2].lower[size_t(k)] * strideK;
    for (int32_t j = 0; j < dims[1]; ++j) {
      const double wj = axes[1].upperWeight[size_t(j)];
      const int64_t baseJK = baseK + axes[1].lower[size_t(j)] * strideJ;
      for (int32_t i = 0; i < dims[0]; ++i, ++target) {
        const double wi = axes[0].upperWeight[size_t(i)];
        const VoxelCode* c = codes + baseJK + axes[0].lower[size_t(i)];
        const auto along = [&](const VoxelCode* p) { return (1 - wi) * p[0] + wi * p[stepI]; };
        const double front = (1 - wj) * along(c) + wj * along(c + stepJ);
        const double back = (1 - wj) * along(c + stepK) + wj * along(c + stepK + stepJ);
        const double value = (1 - wk) * front + wk * back;
        out[target] = VoxelCode(std::clamp(std::round(value), kCodeMin, kCodeMax));
      }
    }
  }
  return result;
}

}  // namespace trephine::formats
