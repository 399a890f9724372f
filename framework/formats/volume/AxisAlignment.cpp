#include "framework/formats/volume/AxisAlignment.h"

#include <cmath>
#include <sstream>

#include "framework/core/Strings.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

namespace {

std::string describe(const Vec3& v) {
  return "(" + formatDouble(v.x()) + ", " + formatDouble(v.y()) + ", " + formatDouble(v.z()) + ")";
}

}  // namespace

bool isAxisAligned(const Eigen::Matrix3d& axes) {
  std::array<bool, 3> taken{false, false, false};
  for (int a = 0; a < 3; ++a) {
    const Vec3 step = axes.col(a);
    const double length = step.norm();
    if (!(length > 0) || !std::isfinite(length)) return true;  // degenerate: alignGrid says why
    int dominant = 0;
    step.cwiseAbs().maxCoeff(&dominant);
    for (int w = 0; w < 3; ++w)
      if (w != dominant && std::abs(step[w]) > kAxisAlignmentTolerance * length) return false;
    if (taken[dominant]) return false;
    taken[dominant] = true;
  }
  return true;
}

AlignedGrid alignGrid(const std::array<int64_t, 3>& storedDims, const Eigen::Matrix3d& axes, const Vec3& origin,
                      const std::filesystem::path& file) {
  if (!origin.allFinite()) throw VolumeReadError(file, "origin " + describe(origin) + " is not finite");
  AlignedGrid grid;
  std::array<int, 3> worldAxisOf{-1, -1, -1};  // stored axis -> world axis
  std::array<bool, 3> flipped{false, false, false};
  std::array<int, 3> storedAxisOf{-1, -1, -1};  // world axis -> stored axis
  for (int a = 0; a < 3; ++a) {
    const Vec3 step = axes.col(a);
    const double length = step.norm();
    if (!step.allFinite() || !(length > 0) || !std::isfinite(length))
      throw VolumeReadError(file, "the direction of axis " + std::to_string(a) + " " + describe(step) +
                                      " has no length (expected a non-zero voxel step in mm)");
    int dominant = 0;
    step.cwiseAbs().maxCoeff(&dominant);
    for (int w = 0; w < 3; ++w) {
      if (w != dominant && std::abs(step[w]) > kAxisAlignmentTolerance * length)
        throw VolumeReadError(file, "oblique orientations are not supported (axis " + std::to_string(a) +
                                        " points along " + describe(step / length) +
                                        "); resample the file onto an axis-aligned grid first, e.g. with "
                                        "SimpleITK or 3D Slicer");
    }
    if (storedAxisOf[dominant] >= 0)
      throw VolumeReadError(file, "axes " + std::to_string(storedAxisOf[dominant]) + " and " + std::to_string(a) +
                                      " both point along world axis " + std::to_string(dominant) +
                                      " (expected three independent directions)");
    storedAxisOf[dominant] = a;
    worldAxisOf[a] = dominant;
    flipped[a] = step[dominant] < 0;
    grid.dims[dominant] = static_cast<int32_t>(storedDims[a]);
    grid.spacing[dominant] = length;
  }
  // Output strides (i fastest) and the stored-to-output index map.
  const std::array<int64_t, 3> stride{1, int64_t(grid.dims[0]), int64_t(grid.dims[0]) * grid.dims[1]};
  grid.origin = origin;
  grid.placement.dims = storedDims;
  grid.placement.base = 0;
  for (int a = 0; a < 3; ++a) {
    const int64_t s = stride[worldAxisOf[a]];
    if (flipped[a]) {
      // Stored index 0 becomes the last aligned index: the aligned origin is the far stored sample.
      grid.placement.step[a] = -s;
      grid.placement.base += (storedDims[a] - 1) * s;
      grid.origin += double(storedDims[a] - 1) * axes.col(a);
    } else {
      grid.placement.step[a] = s;
    }
  }
  const Vec3 farCorner = grid.origin + Vec3(grid.dims[0] * grid.spacing.x(), grid.dims[1] * grid.spacing.y(),
                                            grid.dims[2] * grid.spacing.z());
  if (!grid.origin.allFinite() || !farCorner.allFinite())
    throw VolumeReadError(file, "the volume does not fit in finite coordinates (origin " + describe(origin) + ")");
  return grid;
}

}  // namespace trephine::formats
