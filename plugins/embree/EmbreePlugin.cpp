// A triangle engine on Embree's ray tracing kernels: a collision back-end of
// every target that keeps its surface as triangles (the skull, the brain).
#include "framework/core/Registry.h"
#include "plugins/embree/EmbreeEngine.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.addTriangleEngine<trephine::embree::EmbreeEngine>(
      "embree",
      "The target's surface as triangles in Embree BVHs (the skull's isosurface in blocks of 16^3 cells, the brain's "
      "boundary faces refitted to the node positions every frame): a spherical burr as the exact sphere, its "
      "distance and a depth- and area-weighted normal by closest-point queries, inside by ray parity; another "
      "shell point by point (the skull only); sweeps sampled every half voxel or half edge and refined by bisection");
}
