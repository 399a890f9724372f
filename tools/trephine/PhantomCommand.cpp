#include "tools/trephine/PhantomCommand.h"

#include <iostream>
#include <string_view>

#include "plugins/tetra_brain/TetPhantoms.h"
#include "plugins/tetra_brain/io/MeditWriter.h"
#include "plugins/voxel_skull/Phantoms.h"
#include "plugins/voxel_skull/io/VolumeWriter.h"

namespace trephine::cli {

namespace {

constexpr const char* kUsageLine =
    "usage: trephine phantom SPEC --out FILE.mha|FILE.mhd [--raw]   (a volume)\n"
    "       trephine phantom SPEC --out FILE.mesh|FILE.mesh.gz     (a tetrahedral mesh)\n";

// The output file's name decides which kind of phantom SPEC names: the same
// name (cube) is a voxel phantom in a volume and a tetrahedral one in a mesh.
enum class PhantomKind { kVolume, kTetMesh, kUnknown };

PhantomKind kindFromFileName(std::string_view file) {
  if (file.ends_with(".mesh") || file.ends_with(".mesh.gz")) return PhantomKind::kTetMesh;
  if (file.ends_with(".mha") || file.ends_with(".mhd")) return PhantomKind::kVolume;
  return PhantomKind::kUnknown;
}

void writeVolumePhantom(const std::string& spec, const std::string& out, bool compress) {
  const voxel::DensityVolume volume = voxel::makePhantom(spec);
  voxel::writeMetaImage(volume, out, compress);
  const auto& d = volume.dims();
  std::cout << out << ": " << d[0] << " x " << d[1] << " x " << d[2] << " voxels of " << volume.spacing().x()
            << " mm, densities " << volume.minDensity() << " to " << volume.maxDensity() << "\n";
}

void writeTetPhantom(const std::string& spec, const std::string& out) {
  const tetra::TetMesh mesh = tetra::makeTetPhantom(spec);
  tetra::writeMeditMesh(mesh, out);
  std::cout << out << ": " << mesh.nodeCount() << " nodes, " << mesh.tetCount() << " tetrahedra\n";
}

}  // namespace

int phantomCommand(const Arguments& arguments) {
  if (arguments.positional.size() != 1 || !arguments.has("--out")) {
    std::cerr << kUsageLine << "volume phantoms (.mha, .mhd):\n"
              << voxel::phantomHelp() << "tetrahedral phantoms (.mesh, .mesh.gz):\n"
              << tetra::tetPhantomHelp();
    return kUsage;
  }
  const std::string spec = arguments.positional[0];
  const std::string out = *arguments.get("--out");
  const PhantomKind kind = kindFromFileName(out);
  if (kind == PhantomKind::kUnknown) {
    std::cerr << "trephine phantom: cannot tell what to write to '" << out
              << "': expected .mha or .mhd (a volume) or .mesh or .mesh.gz (a tetrahedral mesh)\n";
    return kUsage;
  }
  if (kind == PhantomKind::kTetMesh && arguments.has("--raw")) {
    std::cerr << "trephine phantom: --raw is for volumes (.mha, .mhd); a .mesh is plain text, a .mesh.gz gzipped\n";
    return kUsage;
  }
  try {
    if (kind == PhantomKind::kTetMesh) {
      writeTetPhantom(spec, out);
    } else {
      writeVolumePhantom(spec, out, !arguments.has("--raw"));
    }
  } catch (const std::exception& e) {
    std::cerr << "trephine phantom: " << e.what() << "\n";
    return kSceneError;
  }
  return kOk;
}

}  // namespace trephine::cli
