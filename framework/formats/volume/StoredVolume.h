#pragma once
// What a volume header says about its samples, in the terms shared by all
// formats, and the step that turns those samples into a DensityVolume
// (orientation, then int16 encoding). Also the size limits every reader
// checks before it allocates anything.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "framework/math/Math.h"
#include "framework/data/DensityVolume.h"
#include "framework/formats/volume/SampleConversion.h"

namespace trephine::formats {

// At most 2^31 voxels (4 GiB of codes): anything larger is a corrupt header
// or far beyond what an interactive simulation can hold.
inline constexpr uint64_t kMaxVoxels = uint64_t(1) << 31;
// Text headers (MetaImage, NRRD, including NRRD data file lists) above this are refused.
inline constexpr uint64_t kMaxHeaderBytes = uint64_t(1) << 20;

struct StoredVolume {
  std::array<int64_t, 3> dims{0, 0, 0};  // samples along the stored axes, first fastest
  SampleLayout layout;
  SampleScaling scaling;
  // Column a: world step (mm) from one sample to the next along stored axis a
  // (direction times spacing).
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Vec3 origin = Vec3::Zero();  // mm, world position of the centre of stored sample (0, 0, 0)

  uint64_t voxelCount() const { return uint64_t(dims[0]) * uint64_t(dims[1]) * uint64_t(dims[2]); }
  uint64_t byteCount() const { return voxelCount() * byteSize(layout.type); }
};

// The patient frame a file's world coordinates are in. The scene's world is
// LPS (as DICOM, ITK and MetaImage: +x toward the patient's left, +y
// posterior, +z superior); every reader converts into it.
enum class PatientFrame {
  kLps,  // DICOM, MetaImage, NRRD "left-posterior-superior": as it is
  kRas,  // NIfTI's qform and sform, NRRD "right-anterior-superior" (3D Slicer's)
  kLas,  // NRRD "left-anterior-superior"
  kNone  // no patient frame (NRRD scanner-xyz, NIfTI without qform or sform): as it is
};
// Turns `stored`'s axes and origin from `frame` into the scene's LPS.
void convertToLps(StoredVolume& stored, PatientFrame frame);

// Checks that `dims` (as read from the header field `field`) are positive and
// within kMaxVoxels, before anything is sized from them.
void checkDimensions(const std::array<int64_t, 3>& dims, const std::string& field, const std::filesystem::path& file);

// Builds the volume from `samples` (exactly stored.byteCount() bytes in stored order).
DensityVolume assembleVolume(const StoredVolume& stored, std::span<const uint8_t> samples,
                             const std::filesystem::path& file);

}  // namespace trephine::formats
