// Collision back-ends on Embree's ray tracing kernels.
#include "framework/core/Registry.h"
#include "plugins/embree/EmbreeVoxelBackend.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.addBackend<trephine::embree::EmbreeVoxelBackend>(
      "VoxelSkull", "embree",
      "The skull's isosurface as triangles in an Embree BVH: exact sphere distance by closest-point queries, inside "
      "by ray parity, sweeps by conservative advancement");
}
