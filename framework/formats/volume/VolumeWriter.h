#pragma once
// Writing a DensityVolume as MetaImage, the format ITK, 3D Slicer and
// ParaView all read. Samples are little-endian MET_SHORT when the codes are
// the densities (scale 1, offset 0), otherwise MET_FLOAT densities, so
// readVolume gives back the same densities (to float precision).
#include <filesystem>
#include <stdexcept>
#include <string>

#include "framework/core/AtomicFile.h"
#include "framework/data/DensityVolume.h"

namespace trephine::formats {

using VolumeWriteError = FileWriteError;  // the message starts with the file

// `file` ending in .mha: one file (ElementDataFile = LOCAL); ending in .mhd:
// the header plus <stem>.raw, or <stem>.zraw when `compress` (zlib). Each file
// is written under a temporary name and renamed into place, so a failed write
// leaves no partial file. Throws VolumeWriteError naming the file.
void writeMetaImage(const DensityVolume& volume, const OutputPath& file, bool compress);

}  // namespace trephine::formats
