#pragma once
// Reading a DICOM series (CT or MR) into a DensityVolume, with GDCM (all of
// it in DicomReader.cpp). `path` is a directory holding one series (files of
// other series too, then `seriesUid` picks one), or one file (a single
// slice, or a multi-frame image).
//   - Slices are sorted by their position along the normal of the image
//     plane (ImagePositionPatient against ImageOrientationPatient), not by
//     file name or InstanceNumber; the slice step is taken from the
//     positions, not from SliceThickness.
//   - Stored values become densities by RescaleSlope and RescaleIntercept
//     (CT in Hounsfield units).
//   - The world frame is DICOM's patient frame (LPS: x to the patient's left,
//     y posterior, z superior), in mm. Grids whose axes are a signed
//     permutation of it are reordered (AxisAlignment); oblique and
//     gantry-tilted series are resampled onto an axis-aligned grid.
//   - Slice steps within 1% of the series' step are even; within 10%
//     (positions a scanner rounded), the series is resampled onto even steps
//     by linear interpolation, with a warning giving the spread; beyond, an
//     error. Zeros after a file's data set (padding) are ignored, with a note.
//   - A missing slice (a gap of more than 1.5 steps), two slices at one
//     position, slices of different sizes or orientations, several series
//     without a choice, or a file GDCM cannot read or decode: a
//     VolumeReadError naming the file (or the directory) and the problem.
#include <filesystem>
#include <span>
#include <string>

#include "framework/data/DensityVolume.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

// A DICOM Part 10 file: "DICM" after the 128-byte preamble.
bool looksLikeDicom(std::span<const uint8_t> head);

DensityVolume readDicom(const std::filesystem::path& path, const std::string& seriesUid = "",
                        VolumeReadNotes* notes = nullptr);

}  // namespace trephine::formats
