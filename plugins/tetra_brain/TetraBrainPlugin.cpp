// Deformable brains as tetrahedral meshes: collision of pointshell tools.
#include "framework/core/Registry.h"
#include "plugins/tetra_brain/ScriptedDeformation.h"
#include "plugins/tetra_brain/TetraBrain.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::tetra::TetraBrain>(
      "TetraBrain", "Brain as a tetrahedral mesh: pointshell collision through a uniform grid (Algorithm 2)");
  registrar.add<trephine::tetra::ScriptedDeformation>(
      "ScriptedDeformation", "Moves a TetraBrain's nodes by a prescribed wave or bump (tests and benchmarks)");
}
