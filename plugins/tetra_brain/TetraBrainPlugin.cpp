// Deformable brains as tetrahedral meshes: collision of pointshell tools.
#include <string>

#include "framework/core/Registry.h"
#include "plugins/tetra_brain/MeshTetBackend.h"
#include "plugins/tetra_brain/NativeTetBackend.h"
#include "plugins/tetra_brain/ScriptedDeformation.h"
#include "plugins/tetra_brain/PlacedTumour.h"
#include "plugins/tetra_brain/Resection.h"
#include "plugins/tetra_brain/TetGridRebuild.h"
#include "plugins/tetra_brain/Tissue.h"
#include "plugins/tetra_brain/TetPhantoms.h"
#include "plugins/tetra_brain/TetraBrain.h"
#include "plugins/tetra_brain/cell_size/CellSizeCommands.h"
#include "framework/formats/mesh/MeditWriter.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::tetra::TetraBrain>(
      "TetraBrain", "Brain as a tetrahedral mesh: pointshell collision through a uniform grid (Algorithm 2)");
  registrar.addBackend<trephine::tetra::NativeTetBackend>(
      "TetraBrain", "native",
      "The thesis's method: shell points located in tetrahedra through a uniform grid, depth from the boundary "
      "faces");
  // Every triangle engine (embree, bullet) is a back-end too, on the boundary faces.
  registrar.addEngineAdapter("TetraBrain", [](std::unique_ptr<trephine::CollisionBackend> engine) {
    return trephine::adaptEngine<trephine::tetra::MeshTetBackend>(std::move(engine));
  });
  registrar.add<trephine::tetra::ScriptedDeformation>(
      "ScriptedDeformation", "Moves a TetraBrain's nodes by a prescribed wave or bump (tests and benchmarks)");
  registrar.add<trephine::tetra::PlacedTumour>(
      "PlacedTumour", "A tumour placed in a brain mesh that has none: the tetrahedra of a ball take a label of their own");
  registrar.add<trephine::tetra::Tissue>(
      "Tissue", "One tissue of a brain (the tetrahedra of one label): its resistance to removal, its vascularity, "
                "whether it is critical");
  registrar.add<trephine::tetra::Resection>(
      "Resection", "Resection of a brain's tissues: checks the tissues declared against the mesh's labels and "
                   "measures what is removed");
  registrar.add<trephine::tetra::TetGridRebuild>(
      "TetGridRebuild",
      "Builds the native back-end's grids again on the deformed shape, off the haptic thread, when the nodes drift "
      "beyond a fraction of the displacement margin");
  registrar.addPhantomWriter({.kind = "tetrahedral mesh",
                              .suffixes = {".mesh", ".mesh.gz"},
                              .plugin = {},
                              .help = trephine::tetra::tetPhantomHelp(),
                              .canWriteRaw = false,
                              .write = [](const std::string& specification, const std::string& file, bool) {
                                const trephine::TetMesh mesh = trephine::tetra::makeTetPhantom(specification);
                                trephine::formats::writeMeditMesh(mesh, file);
                                return std::to_string(mesh.nodeCount()) + " nodes, " + std::to_string(mesh.tetCount()) +
                                       " tetrahedra";
                              }});
  // `trephine cellsize`: the grid cell-size experiments (the program links only the framework).
  registrar.addService<trephine::PluginCommands>(trephine::tetra::makeCellSizeCommands());
}
