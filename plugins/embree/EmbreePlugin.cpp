// Collision back-ends on Embree's ray tracing kernels.
#include "framework/core/Registry.h"
#include "plugins/embree/EmbreeTetBackend.h"
#include "plugins/embree/EmbreeVoxelBackend.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.addBackend<trephine::embree::EmbreeVoxelBackend>(
      "VoxelSkull", "embree",
      "The skull's isosurface as triangles in an Embree BVH: exact sphere distance and a depth- and area-weighted "
      "normal by closest-point queries, inside by ray parity, sweeps sampled every half voxel and refined by "
      "bisection");
  registrar.addBackend<trephine::embree::EmbreeTetBackend>(
      "TetraBrain", "embree",
      "The brain's boundary faces as triangles in an Embree BVH, refitted to the node positions every frame: exact "
      "sphere distance by closest-point queries, inside by ray parity, sweeps sampled every half edge");
}
