#include "framework/data/DensityVolume.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace trephine {

namespace {
constexpr int32_t kCodeMin = std::numeric_limits<VoxelCode>::min();
constexpr int32_t kCodeMax = std::numeric_limits<VoxelCode>::max();
}  // namespace

int32_t DensityEncoding::thresholdCode(double density) const {
  // code > (density - offset) / scale  <=>  code >= floor(...) + 1
  const double c = std::floor((density - offset) / scale) + 1.0;
  if (!(c > kCodeMin)) return kCodeMin;   // also NaN: everything is solid
  if (c > kCodeMax) return kCodeMax + 1;  // nothing is solid
  return static_cast<int32_t>(c);
}

DensityEncoding DensityEncoding::fit(double minValue, double maxValue, bool allIntegers) {
  DensityEncoding e;
  if (allIntegers && maxValue - minValue <= double(kCodeMax) - double(kCodeMin)) {
    // Shift only when the values do not fit as they are (uint16 above 32767).
    if (minValue >= kCodeMin && maxValue <= kCodeMax) return e;
    e.offset = minValue - kCodeMin;
    return e;
  }
  const double span = maxValue - minValue;
  // Never below the smallest normal double: a subnormal scale has no finite
  // reciprocal, and encoding divides by it.
  e.scale = span > 0 ? std::max(span / (double(kCodeMax) - double(kCodeMin)), std::numeric_limits<double>::min()) : 1.0;
  e.offset = minValue - e.scale * kCodeMin;
  return e;
}

DensityVolume::DensityVolume(std::array<int32_t, 3> dims, Vec3 spacing, Vec3 origin, DensityEncoding encoding)
    : m_dims(dims), m_spacing(spacing), m_origin(origin), m_encoding(encoding) {
  for (int a = 0; a < 3; ++a) {
    if (dims[a] <= 0) throw std::invalid_argument("volume dimensions must be positive");
    if (!(spacing[a] > 0) || !std::isfinite(spacing[a])) throw std::invalid_argument("voxel spacing must be positive");
  }
  if (!origin.allFinite()) throw std::invalid_argument("volume origin must be finite");
  m_codes.assign(size_t(dims[0]) * size_t(dims[1]) * size_t(dims[2]), VoxelCode(0));
}

void DensityVolume::setDensity(int32_t i, int32_t j, int32_t k, double density) {
  const double c = std::round((density - m_encoding.offset) / m_encoding.scale);
  m_codes[index(i, j, k)] = static_cast<VoxelCode>(std::clamp(c, double(kCodeMin), double(kCodeMax)));
}

Box3 DensityVolume::bounds() const {
  const Vec3 lo = m_origin - 0.5 * m_spacing;
  const Vec3 size(m_dims[0] * m_spacing.x(), m_dims[1] * m_spacing.y(), m_dims[2] * m_spacing.z());
  return Box3(lo, lo + size);
}

double DensityVolume::minDensity() const {
  if (m_codes.empty()) return 0;
  return m_encoding.density(*std::min_element(m_codes.begin(), m_codes.end()));
}

double DensityVolume::maxDensity() const {
  if (m_codes.empty()) return 0;
  return m_encoding.density(*std::max_element(m_codes.begin(), m_codes.end()));
}

}  // namespace trephine
