#include "tools/trephine/PhantomCommand.h"

#include <iostream>

#include "plugins/voxel_skull/Phantoms.h"
#include "plugins/voxel_skull/io/VolumeWriter.h"

namespace trephine::cli {

int phantomCommand(const Arguments& arguments) {
  if (arguments.positional.size() != 1 || !arguments.has("--out")) {
    std::cerr << "usage: trephine phantom SPEC --out FILE.mha|FILE.mhd [--raw]\nphantoms:\n" << voxel::phantomHelp();
    return kUsage;
  }
  const std::string spec = arguments.positional[0];
  const std::string out = *arguments.get("--out");
  try {
    const voxel::DensityVolume volume = voxel::makePhantom(spec);
    voxel::writeMetaImage(volume, out, !arguments.has("--raw"));
    const auto& d = volume.dims();
    std::cout << out << ": " << d[0] << " x " << d[1] << " x " << d[2] << " voxels of " << volume.spacing().x()
              << " mm, densities " << volume.minDensity() << " to " << volume.maxDensity() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "trephine phantom: " << e.what() << "\n";
    return kSceneError;
  }
  return kOk;
}

}  // namespace trephine::cli
