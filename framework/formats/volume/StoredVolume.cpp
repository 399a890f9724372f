#include "framework/formats/volume/StoredVolume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "framework/core/Strings.h"
#include "framework/formats/volume/AxisAlignment.h"
#include "framework/formats/volume/ObliqueResampling.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

void checkDimensions(const std::array<int64_t, 3>& dims, const std::string& field, const std::filesystem::path& file) {
  const std::string shown = std::to_string(dims[0]) + " " + std::to_string(dims[1]) + " " + std::to_string(dims[2]);
  uint64_t voxels = 1;
  for (int64_t n : dims) {
    if (n <= 0) throw VolumeReadError(file, field + " " + shown + " must be positive");
    if (uint64_t(n) > kMaxVoxels || voxels * uint64_t(n) > kMaxVoxels) {
      throw VolumeReadError(file, field + " " + shown + " is more than the " + std::to_string(kMaxVoxels) +
                                      " voxels supported (the header is corrupt or the volume must be cropped or "
                                      "downsampled first)");
    }
    voxels *= uint64_t(n);
  }
  if (std::max({dims[0], dims[1], dims[2]}) > std::numeric_limits<int32_t>::max())
    throw VolumeReadError(file, field + " " + shown + " exceeds the largest supported axis length");
}

DensityVolume assembleVolume(const StoredVolume& stored, std::span<const uint8_t> samples,
                             const std::filesystem::path& file) {
  checkDimensions(stored.dims, "dimensions", file);
  if (samples.size() != stored.byteCount())
    throw VolumeReadError(file, "internal error: " + std::to_string(samples.size()) + " bytes of samples for " +
                                    std::to_string(stored.byteCount()));
  const SampleRange range = scanSamples(samples, stored.layout, stored.scaling);
  if (range.firstNonFinite) {
    const size_t n = *range.firstNonFinite;
    const size_t i = n % size_t(stored.dims[0]);
    const size_t j = (n / size_t(stored.dims[0])) % size_t(stored.dims[1]);
    const size_t k = n / (size_t(stored.dims[0]) * size_t(stored.dims[1]));
    throw VolumeReadError(file, "voxel (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                                    ") (sample " + std::to_string(n) +
                                    " in file order) is NaN or infinite (expected finite densities)");
  }
  if (!std::isfinite(range.max - range.min))
    throw VolumeReadError(file, "the density range " + formatDouble(range.min) + " to " + formatDouble(range.max) +
                                    " is too wide to encode");
  const DensityEncoding encoding = DensityEncoding::fit(range.min, range.max, range.allIntegers);

  if (!isAxisAligned(stored.axes)) {
    // Codes in stored order, then interpolated onto the aligned grid (codes
    // are affine in density, so this is interpolation of densities).
    std::vector<VoxelCode> storedCodes(stored.voxelCount());
    const SamplePlacement identity{stored.dims, {1, stored.dims[0], stored.dims[0] * stored.dims[1]}, 0};
    encodeSamples(samples, stored.layout, stored.scaling, encoding, identity, storedCodes);
    const ResampledGrid grid = resampledGrid(stored.dims, stored.axes, stored.origin, file);
    DensityVolume volume(grid.dims, grid.spacing, grid.origin, encoding);
    const VoxelCode air = *std::min_element(storedCodes.begin(), storedCodes.end());
    resampleCodes(storedCodes, stored.dims, stored.axes, stored.origin, grid, air, volume.codeVector());
    return volume;
  }
  const AlignedGrid grid = alignGrid(stored.dims, stored.axes, stored.origin, file);
  DensityVolume volume(grid.dims, grid.spacing, grid.origin, encoding);
  encodeSamples(samples, stored.layout, stored.scaling, encoding, grid.placement, volume.codeVector());
  return volume;
}

void convertToLps(StoredVolume& stored, PatientFrame frame) {
  // RAS to LPS negates x and y; LAS to LPS, y alone.
  Vec3 flip = Vec3::Ones();
  if (frame == PatientFrame::kRas) flip = Vec3(-1, -1, 1);
  if (frame == PatientFrame::kLas) flip = Vec3(1, -1, 1);
  stored.axes = flip.asDiagonal() * stored.axes;
  stored.origin = flip.asDiagonal() * stored.origin;
}

}  // namespace trephine::formats
