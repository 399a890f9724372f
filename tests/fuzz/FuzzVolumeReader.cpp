// libFuzzer target: arbitrary bytes as a volume file. The first byte picks
// the extension (.mha, .nrrd or .nii; the readers detect the format from the
// content, the extension is only the fallback; a DICOM file, "DICM" after its
// 128-byte preamble, goes to the DICOM reader whatever its name), the rest
// is the file. The
// file lives in a directory of its own per process, so relative data file
// names in fuzzed headers resolve inside it. Any crash, sanitizer report,
// hang or exception other than VolumeReadError is a reader bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "framework/formats/volume/VolumeReader.h"
#include "tests/fuzz/FuzzInputFiles.h"

namespace {
const std::filesystem::path& inputDirectory() { return trephine::fuzz::inputDirectory("fuzz_volume_reader"); }
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".mha", ".nrrd", ".nii"};
  const std::filesystem::path file = inputDirectory() / (std::string("input") + kExtensions[data[0] % 3]);
  trephine::fuzz::writeInputFile(file, data + 1, size - 1);
  try {
    const trephine::DensityVolume volume = trephine::formats::readVolume(file);
    // A volume that was read is usable: codes for every voxel, positive spacing, finite bounds.
    const auto& dims = volume.dims();
    if (volume.voxelCount() != size_t(dims[0]) * size_t(dims[1]) * size_t(dims[2])) __builtin_trap();
    if (!(volume.spacing().minCoeff() > 0) || !volume.bounds().min().allFinite() || !volume.bounds().max().allFinite())
      __builtin_trap();
    if (!(volume.encoding().scale > 0) || !std::isfinite(volume.encoding().offset)) __builtin_trap();
  } catch (const trephine::formats::VolumeReadError& error) {
    // The message names a file (this one or a data file it refers to) before the problem.
    if (std::string(error.what()).find(": ") == std::string::npos) __builtin_trap();
  }
  std::filesystem::remove(file);
  return 0;
}
