#pragma once
// A segmentation file (NRRD, NIfTI, MetaImage, a DICOM series; anything the
// volume readers take) as a labelled image for the mesher: integer labels,
// all non-zero ones kept or only those listed.
#include <filesystem>
#include <string>
#include <vector>

#include "framework/meshing/TetMeshing.h"

namespace trephine::cli {

struct LabelledImageInput {
  LabelledImage image;
  std::vector<int32_t> labels;  // the labels present after selection, ascending
  size_t labelledVoxels = 0;
};

// Throws std::runtime_error naming the file for a value that is not a
// whole number, a label out of range, or a listed label that no voxel holds.
LabelledImageInput readLabelledImage(const std::filesystem::path& file, const std::vector<int32_t>& keep);

// "3,42,..." to labels; throws std::invalid_argument saying what was expected.
std::vector<int32_t> parseLabelList(const std::string& text);

}  // namespace trephine::cli
