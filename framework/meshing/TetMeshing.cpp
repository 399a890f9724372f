#include "framework/meshing/TetMeshing.h"

#include <map>
#include <memory>
#include <mutex>

#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"

namespace trephine {

namespace {

// A loader and the registry the meshing plugin registered into, kept for
// the process's life: the mesher's code lives in the loaded module.
struct LoadedMesher {
  std::unique_ptr<PluginLoader> loader;
  Registry registry;
  const TetMesher* mesher = nullptr;
  std::string problem;  // why there is no mesher
};

std::string missingMessage(std::string_view feature, const std::string& problem) {
  return std::string(feature) +
         " needs the meshing plugin (CGAL Mesh_3, GPL-3.0-or-later), which is not available here (" + problem +
         "); the brain and sphere phantoms, `trephine mesh` and labelled-image meshing come with it (configure "
         "with -DTREPHINE_WITH_MESHING=ON and libcgal-dev installed, or set TREPHINE_PLUGIN_PATH to the folder "
         "of trephine_meshing.so), or load a tetrahedral mesh file instead";
}

void load(LoadedMesher& loaded) {
  if (const auto error = loaded.loader->load("meshing", loaded.registry)) {
    loaded.problem = *error;
    return;
  }
  loaded.mesher = loaded.registry.service<TetMesher>();
  if (!loaded.mesher) loaded.problem = "the plugin 'meshing' registers no TetMesher";
}

std::mutex& loadMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

TetMesher::~TetMesher() = default;

MeshingUnavailable::MeshingUnavailable(const std::string& what) : std::runtime_error(what) {}

const TetMesher& tetMesher(std::string_view feature) {
  static LoadedMesher loaded;
  static bool tried = false;
  {
    const std::lock_guard lock(loadMutex());
    if (!tried) {
      loaded.loader = std::make_unique<PluginLoader>();
      load(loaded);
      tried = true;
    }
  }
  if (!loaded.mesher) throw MeshingUnavailable(missingMessage(feature, loaded.problem));
  return *loaded.mesher;
}

const TetMesher& tetMesherFrom(const std::vector<std::filesystem::path>& searchPath, std::string_view feature) {
  static std::map<std::vector<std::filesystem::path>, std::unique_ptr<LoadedMesher>> loadedBySearchPath;
  const std::lock_guard lock(loadMutex());
  std::unique_ptr<LoadedMesher>& loaded = loadedBySearchPath[searchPath];
  if (!loaded) {
    loaded = std::make_unique<LoadedMesher>();
    loaded->loader = std::make_unique<PluginLoader>(searchPath);
    load(*loaded);
  }
  if (!loaded->mesher) throw MeshingUnavailable(missingMessage(feature, loaded->problem));
  return *loaded->mesher;
}

bool meshingAvailable() {
  try {
    tetMesher();
    return true;
  } catch (const MeshingUnavailable&) {
    return false;
  }
}

TetMesh meshImplicitSolid(const ImplicitSolid& solid, int targetTets) {
  return tetMesher("meshing a solid into tetrahedra").meshImplicitSolid(solid, targetTets);
}

TetMesh meshImplicitSolidAtSize(const ImplicitSolid& solid, double size) {
  return tetMesher("meshing a solid into tetrahedra").meshImplicitSolidAtSize(solid, size);
}

TetMesh meshLabelledImage(const LabelledImage& image, int targetTets) {
  return tetMesher("meshing a labelled image into tetrahedra").meshLabelledImage(image, targetTets);
}

TetMesh meshLabelledImageAtSize(const LabelledImage& image, double size) {
  return tetMesher("meshing a labelled image into tetrahedra").meshLabelledImageAtSize(image, size);
}

}  // namespace trephine
