// libFuzzer target: what `trephine view` reads of a run besides the VTK
// files' surfaces, as arbitrary bytes. The first byte picks the file (0: the
// cut voxels, skull_removed.csv, beside a 12^3 skull_density.mhd and a
// skull_volume.json; 1: skull_volume.json; 2: a brain .vtu, whose arrays
// give the colour ranges); the rest is the file. Any crash, sanitizer report
// or exception other than ViewerDataError (whose message names the file and
// says what is wrong) is a bug; so is a packed volume whose sizes do not
// match its header, or a range that is negative or not finite.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "framework/data/DensityVolume.h"
#include "framework/formats/volume/VolumeWriter.h"
#include "framework/runtime/RunViewer.h"
#include "plugins/viewer/MeshColourRanges.h"
#include "plugins/viewer/ViewerVolume.h"
#include "tests/fuzz/FuzzInputFiles.h"

namespace {

const std::filesystem::path& directory() {
  static const std::filesystem::path& d = [] () -> const std::filesystem::path& {
    const std::filesystem::path& dir = trephine::fuzz::inputDirectory("fuzz_viewer_data");
    trephine::DensityVolume volume({12, 12, 12}, trephine::Vec3(1, 1, 1), trephine::Vec3(0, 0, 0));
    for (int k = 0; k < 12; ++k)
      for (int j = 0; j < 12; ++j)
        for (int i = 0; i < 12; ++i) volume.setDensity(i, j, k, (i + j + k) % 7 * 300.0);
    trephine::formats::writeMetaImage(volume, dir / "skull_density.mhd", true);
    return dir;
  }();
  return d;
}

void writeJson(const char* text) {
  trephine::fuzz::writeInputFile(directory() / "skull_volume.json", reinterpret_cast<const uint8_t*>(text),
                                 std::strlen(text));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const int which = data[0] % 3;
  const std::filesystem::path& dir = directory();
  try {
    if (which == 2) {
      trephine::fuzz::writeInputFile(dir / "brain.vtu", data + 1, size - 1);
      for (const auto& [name, value] : trephine::viewer::meshColourRanges({dir / "brain.vtu"}))
        if (!(std::isfinite(value) && value >= 0)) __builtin_trap();
      return 0;
    }
    if (which == 0) {
      writeJson("{\"isovalue\": 400}");
      trephine::fuzz::writeInputFile(dir / "skull_removed.csv", data + 1, size - 1);
    } else {
      trephine::fuzz::writeInputFile(dir / "skull_volume.json", data + 1, size - 1);
      trephine::fuzz::writeInputFile(dir / "skull_removed.csv", reinterpret_cast<const uint8_t*>("i,j,k,t\n"), 8);
    }
    const auto packed = trephine::viewer::packSkullVolume(dir, 512);
    if (!packed) __builtin_trap();  // the density file is there
    uint32_t dims[3], count = 0;
    std::memcpy(dims, packed->density.data() + 4, sizeof dims);
    if (packed->density.size() != 52 + 2 * size_t(dims[0]) * dims[1] * dims[2]) __builtin_trap();
    std::memcpy(&count, packed->removed.data() + 4, sizeof count);
    if (packed->removed.size() != 8 + 8 * size_t(count) || count > dims[0] * dims[1] * dims[2]) __builtin_trap();
  } catch (const trephine::ViewerDataError& error) {
    if (std::string(error.what()).find(": ") == std::string::npos) __builtin_trap();
  }
  return 0;
}
