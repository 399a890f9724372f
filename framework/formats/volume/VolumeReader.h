#pragma once
// Reading CT volumes from MetaImage (.mha, .mhd), NRRD (.nrrd, .nhdr),
// NIfTI-1 and NIfTI-2 (.nii, .nii.gz) files, and DICOM series (a directory,
// DIR?series=UID, or one DICOM file: DicomReader.h), into a DensityVolume.
//
// World frame: the file's world frame is kept as it is. NIfTI sform/qform
// coordinates are RAS+ (x grows towards the patient's right, y anterior,
// z superior); NRRD and MetaImage coordinates are whatever the file's space
// is (ITK and 3D Slicer write LPS: x left, y posterior). No conversion
// between LPS and RAS is made, so a NIfTI and an ITK MetaImage of the same
// scan differ by a sign on x and y. Lengths are millimetres (NIfTI files in
// metres or micrometres are converted).
//
// The result is axis-aligned: direction matrices that are signed permutations
// of the axes are applied by reordering and flipping the samples, so spacing
// is positive and the origin is the world position of the centre of voxel
// (0, 0, 0) after reordering. Oblique files are refused.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "framework/data/DensityVolume.h"
#include "framework/formats/FileReadError.h"

namespace trephine::formats {

// A file that cannot be read as a volume.
using VolumeReadError = FileReadError;

// What a reader tolerated in a file it read: notes (padding ignored) and
// warnings (data changed to fit, such as a DICOM series resampled onto even
// slice steps), each a sentence naming the file.
struct VolumeReadNotes {
  std::vector<std::string> notes, warnings;
};

// Reads a volume, detecting the format from the file content (falling back
// to the extension). Throws VolumeReadError for anything it cannot read;
// `notes`, when given, gets what was tolerated.
DensityVolume readVolume(const std::filesystem::path& file, VolumeReadNotes* notes = nullptr);

}  // namespace trephine::formats
