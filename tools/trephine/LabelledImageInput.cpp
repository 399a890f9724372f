#include "tools/trephine/LabelledImageInput.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>
#include <stdexcept>

#include "framework/formats/volume/VolumeReader.h"

namespace trephine::cli {

std::vector<int32_t> parseLabelList(const std::string& text) {
  std::vector<int32_t> labels;
  size_t at = 0;
  while (at <= text.size()) {
    const size_t comma = std::min(text.find(',', at), text.size());
    int32_t label = 0;
    const char* first = text.data() + at;
    const char* last = text.data() + comma;
    const auto r = std::from_chars(first, last, label);
    if (first == last || r.ec != std::errc() || r.ptr != last || label < 1)
      throw std::invalid_argument("--labels takes labels of 1 and up separated by commas (e.g. 3,42), not '" + text +
                                  "'");
    labels.push_back(label);
    at = comma + 1;
  }
  return labels;
}

LabelledImageInput readLabelledImage(const std::filesystem::path& file, const std::vector<int32_t>& keep) {
  formats::VolumeReadNotes notes;
  const DensityVolume volume = formats::readVolume(file, &notes);
  // Resampling interpolates, and an interpolated label is a label of neither side.
  if (!notes.warnings.empty())
    throw formats::VolumeReadError(file, "a labelled image is read as stored, and this one cannot be: " +
                                             notes.warnings.front());
  LabelledImageInput input;
  LabelledImage& image = input.image;
  image.dims = volume.dims();
  image.spacing = volume.spacing();
  image.origin = volume.origin();
  image.labels.resize(volume.voxelCount());
  const std::set<int32_t> wanted(keep.begin(), keep.end());
  std::set<int32_t> present;
  for (size_t n = 0; n < volume.voxelCount(); ++n) {
    const double value = volume.encoding().density(volume.code(n));
    const double rounded = std::round(value);
    if (std::abs(value - rounded) > 1e-6 || rounded < 0 || rounded > 1e9) {
      const size_t nx = size_t(image.dims[0]), ny = size_t(image.dims[1]);
      throw std::runtime_error(file.string() + ": voxel (" + std::to_string(n % nx) + ", " +
                               std::to_string(n / nx % ny) + ", " + std::to_string(n / (nx * ny)) + ") holds " +
                               std::to_string(value) +
                               " (expected a segmentation: whole labels of 0 and up, 0 outside)");
    }
    int32_t label = int32_t(rounded);
    if (!wanted.empty() && !wanted.count(label)) label = 0;
    image.labels[n] = label;
    if (label != 0) present.insert(label), ++input.labelledVoxels;
  }
  for (int32_t label : wanted)
    if (!present.count(label))
      throw std::runtime_error(file.string() + ": no voxel holds label " + std::to_string(label) + " of --labels");
  if (present.empty()) throw std::runtime_error(file.string() + ": no voxel holds a label other than 0");
  input.labels.assign(present.begin(), present.end());
  return input;
}

}  // namespace trephine::cli
