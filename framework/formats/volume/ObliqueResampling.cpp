#include "framework/formats/volume/ObliqueResampling.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

#include "framework/formats/volume/StoredVolume.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

ResampledGrid resampledGrid(const std::array<int64_t, 3>& storedDims, const Eigen::Matrix3d& axes, const Vec3& origin,
                            const std::filesystem::path& file) {
  const Vec3 lengths = axes.colwise().norm();
  if (!axes.allFinite() || !(lengths.minCoeff() > 0) || !origin.allFinite())
    throw VolumeReadError(file, "the voxel axes or origin are not finite and non-zero");
  // A volume that is not a volume: its axes nearly lie in one plane.
  const double volumeRatio = std::abs(axes.determinant()) / lengths.prod();
  if (!(volumeRatio > 1e-3)) throw VolumeReadError(file, "the voxel axes lie in one plane (expected three directions)");
  // Axes so small or so large that mapping a point back to voxel indices
  // overflows (found by fuzzing: NaN indices).
  if (!axes.inverse().allFinite())
    throw VolumeReadError(file, "the voxel axes cannot be inverted in double precision (spacings far from a scan's)");
  // Which stored axis each world axis follows: the assignment whose
  // direction cosines have the largest product.
  std::array<int, 3> permutation{0, 1, 2}, best{0, 1, 2};
  double bestScore = -1;
  do {
    double score = 1;
    for (int a = 0; a < 3; ++a) score *= std::abs(axes(permutation[a], a)) / lengths[a];
    if (score > bestScore) bestScore = score, best = permutation;
  } while (std::next_permutation(permutation.begin(), permutation.end()));
  ResampledGrid grid;
  // The step's component along its world axis: a tilted CT keeps its pixel
  // spacing and table step; a rotated plane gets a finer grid, never coarser.
  for (int a = 0; a < 3; ++a) grid.spacing[best[a]] = std::abs(axes(best[a], a));
  // Bounding box of the stored voxel centres.
  Vec3 low = origin, high = origin;
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 index;
    for (int a = 0; a < 3; ++a) index[a] = (corner >> a & 1) ? double(storedDims[a] - 1) : 0.0;
    const Vec3 p = origin + axes * index;
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  std::array<int64_t, 3> dims{};
  for (int w = 0; w < 3; ++w) {
    const double count = std::floor((high[w] - low[w]) / grid.spacing[w] + 1e-9) + 1;
    if (!(count <= double(kMaxVoxels)))
      throw VolumeReadError(file, "resampling the oblique grid onto axis-aligned voxels would take more than " +
                                      std::to_string(kMaxVoxels) + " voxels along world axis " + std::to_string(w) +
                                      " (expected axes of a scan, not nearly in one plane)");
    dims[w] = int64_t(count);
  }
  checkDimensions(dims, "the axis-aligned grid resampled from the oblique one", file);
  // A 45-degree plane needs 4 times the stored voxels; far more means axes
  // nearly in one plane, which a corrupt header gives and no scanner.
  const uint64_t stored = uint64_t(storedDims[0]) * uint64_t(storedDims[1]) * uint64_t(storedDims[2]);
  const uint64_t target = uint64_t(dims[0]) * uint64_t(dims[1]) * uint64_t(dims[2]);
  if (target > 16 * stored + 4096)
    throw VolumeReadError(file, "resampling the oblique grid onto axis-aligned voxels would take " +
                                    std::to_string(target) + " voxels for " + std::to_string(stored) +
                                    " stored (expected axes of a scan, not nearly in one plane)");
  for (int w = 0; w < 3; ++w) grid.dims[w] = int32_t(dims[w]);
  grid.origin = low;
  return grid;
}

void resampleCodes(std::span<const VoxelCode> stored, const std::array<int64_t, 3>& storedDims,
                   const Eigen::Matrix3d& axes, const Vec3& origin, const ResampledGrid& grid, VoxelCode background,
                   std::span<VoxelCode> out) {
  const Eigen::Matrix3d toIndex = axes.inverse();
  const Vec3 stepX = toIndex.col(0) * grid.spacing.x();  // stored index change per target x step
  const int64_t strideJ = storedDims[0], strideK = storedDims[0] * storedDims[1];
  size_t n = 0;
  for (int32_t k = 0; k < grid.dims[2]; ++k) {
    for (int32_t j = 0; j < grid.dims[1]; ++j) {
      const Vec3 rowStart = grid.origin + Vec3(0, j * grid.spacing.y(), k * grid.spacing.z());
      Vec3 u = toIndex * (rowStart - origin);
      for (int32_t i = 0; i < grid.dims[0]; ++i, ++n, u += stepX) {
        // Inside the stored cells: within half a voxel of the outer centres.
        int64_t base[3];
        double fraction[3];
        bool inside = true;
        for (int a = 0; a < 3 && inside; ++a) {
          const double last = double(storedDims[a] - 1);
          if (!(u[a] >= -0.5 - 1e-9 && u[a] <= last + 0.5 + 1e-9)) {
            inside = false;  // NaN too: nothing below converts it
            break;
          }
          const double c = std::clamp(u[a], 0.0, last);
          base[a] = std::min<int64_t>(int64_t(c), std::max<int64_t>(storedDims[a] - 2, 0));
          fraction[a] = c - double(base[a]);
        }
        if (!inside) {
          out[n] = background;
          continue;
        }
        const int64_t step[3] = {storedDims[0] > 1 ? 1 : 0, storedDims[1] > 1 ? strideJ : 0,
                                 storedDims[2] > 1 ? strideK : 0};
        const int64_t at = base[0] + base[1] * strideJ + base[2] * strideK;
        double value = 0;
        for (int corner = 0; corner < 8; ++corner) {
          double weight = 1;
          int64_t index = at;
          for (int a = 0; a < 3; ++a) {
            const bool upper = corner >> a & 1;
            weight *= upper ? fraction[a] : 1 - fraction[a];
            if (upper) index += step[a];
          }
          if (weight != 0) value += weight * stored[size_t(index)];
        }
        out[n] = VoxelCode(std::lround(value));
      }
    }
  }
}

}  // namespace trephine::formats
