#pragma once
// Writing a DensityVolume as a DICOM series (GDCM): one CT Image Storage
// file per z slice, axial, the densities as stored values with the rescale
// slope and intercept of the volume's encoding (so a CT in Hounsfield units
// reads back in Hounsfield units). The series is written into a new
// directory beside DIR and renamed into place, so a failed write leaves
// nothing; DIR must not exist or be empty.
#include <filesystem>
#include <string>

#include "framework/data/DensityVolume.h"
#include "framework/formats/volume/VolumeWriter.h"

namespace trephine::formats {

// Throws VolumeWriteError naming the directory.
void writeDicomSeries(const DensityVolume& volume, const std::filesystem::path& directory,
                      const std::string& seriesDescription);

}  // namespace trephine::formats
