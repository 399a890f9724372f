#pragma once
// The skull's volume for the browser viewer (`trephine view`): the densities
// a VtkExporter wrote as the run started (skull_density.mhd) and the voxels
// the drill took (skull_removed.csv), brought to at most `maxVoxels` by
// averaging blocks of f^3 voxels (f the smallest integer that fits), and
// packed as two little-endian binary files:
//   .vol  "VOL1", uint32 nx ny nz, float32 origin[3] (mm, centre of voxel 0),
//         float32 spacing[3] (mm), float32 isovalue (skull_volume.json's, a
//         density; NaN when unknown), offset and scale (a
//         code's density is offset + scale code), then int16 codes, x fastest;
//   .rmv  "RMV1", uint32 count, then count pairs (uint32 voxel of the packed
//         grid, float32 t: the first time, s, the drill took a voxel of it
//         below the isovalue), in time order.
// The viewer colours the skull's surface by the density beneath it and by
// where and when it was cut, and draws the volume itself.
#include <filesystem>
#include <optional>
#include <string>

namespace trephine::viewer {

struct PackedSkullVolume {
  std::string density;  // .vol bytes
  std::string removed;  // .rmv bytes (an empty list when the drill took nothing)
  int factor = 1;       // voxels of the exported volume per packed voxel, each axis
  size_t removedVoxels = 0;  // of the exported volume
};

// From `directory` (a VtkExporter's folder); nothing when it holds no
// skull_density.mhd. Throws ViewerDataError for a file that cannot be read
// or does not fit the volume.
std::optional<PackedSkullVolume> packSkullVolume(const std::filesystem::path& directory, size_t maxVoxels);

// The isovalue a skull_volume.json gives (a density), NaN without the file.
// Throws ViewerDataError for one without a finite "isovalue".
double readSkullIsovalue(const std::filesystem::path& file);

}  // namespace trephine::viewer
