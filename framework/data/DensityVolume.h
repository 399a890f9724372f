#pragma once
// A CT-like density volume on an axis-aligned grid, stored at 2 bytes per
// voxel. Densities are kept as int16 codes with a linear map
// density = offset + scale * code, so int16 and uint16 CT data are stored
// exactly (scale 1) and float data is quantised to 1/65535 of its range.
// Voxel (i, j, k) is centred at origin + (i sx, j sy, k sz) (mm): the
// convention of MetaImage, NRRD (cell-centred) and NIfTI.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "framework/math/Math.h"

namespace trephine {

using VoxelCode = int16_t;

// The linear map from stored codes to densities.
struct DensityEncoding {
  double offset = 0;  // density of code 0
  double scale = 1;   // density per code step (> 0)

  double density(VoxelCode code) const { return offset + scale * code; }
  // The smallest code whose density is above `density` (codes above it are
  // "solid"); clamped to the code range, so an isovalue above every density
  // gives a threshold no code exceeds.
  int32_t thresholdCode(double density) const;
  // Exact (scale 1) when every value is an integer inside int16 after a
  // shift; otherwise [min, max] is spread over the full int16 range.
  static DensityEncoding fit(double minValue, double maxValue, bool allIntegers);
};

class DensityVolume {
 public:
  DensityVolume() = default;
  DensityVolume(std::array<int32_t, 3> dims, Vec3 spacing, Vec3 origin, DensityEncoding encoding = {});

  const std::array<int32_t, 3>& dims() const { return m_dims; }
  const Vec3& spacing() const { return m_spacing; }  // mm, all > 0
  const Vec3& origin() const { return m_origin; }    // mm, centre of voxel (0, 0, 0)
  const DensityEncoding& encoding() const { return m_encoding; }
  size_t voxelCount() const { return m_codes.size(); }

  // Linear index of voxel (i, j, k): i fastest.
  size_t index(int32_t i, int32_t j, int32_t k) const {
    return static_cast<size_t>(i) +
           static_cast<size_t>(m_dims[0]) *
               (static_cast<size_t>(j) + static_cast<size_t>(m_dims[1]) * static_cast<size_t>(k));
  }
  VoxelCode code(size_t linear) const { return m_codes[linear]; }
  double density(int32_t i, int32_t j, int32_t k) const { return m_encoding.density(m_codes[index(i, j, k)]); }
  void setDensity(int32_t i, int32_t j, int32_t k, double density);

  const VoxelCode* codes() const { return m_codes.data(); }
  VoxelCode* codes() { return m_codes.data(); }
  std::vector<VoxelCode>& codeVector() { return m_codes; }

  // World bounds of the voxel cells (mm): from origin - spacing/2 to the far corner.
  Box3 bounds() const;
  Vec3 voxelCenter(int32_t i, int32_t j, int32_t k) const {
    return m_origin + Vec3(i * m_spacing.x(), j * m_spacing.y(), k * m_spacing.z());
  }
  double minDensity() const;
  double maxDensity() const;

 private:
  std::array<int32_t, 3> m_dims{0, 0, 0};
  Vec3 m_spacing = Vec3::Ones();
  Vec3 m_origin = Vec3::Zero();
  DensityEncoding m_encoding;
  std::vector<VoxelCode> m_codes;
};

}  // namespace trephine
