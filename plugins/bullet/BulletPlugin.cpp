// A triangle engine on Bullet's collision world: a collision back-end of
// every target that keeps its surface as triangles (the skull, the brain).
#include "framework/core/Registry.h"
#include "plugins/bullet/BulletEngine.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.addTriangleEngine<trephine::bullet::BulletEngine>(
      "bullet",
      "The target's surface as Bullet triangle meshes (btBvhTriangleMeshShape per block: the skull's isosurface in "
      "blocks of 16^3 cells, the brain's boundary faces refitted to the node positions every frame): the burr as a "
      "Bullet sphere and a shaft as a Bullet cylinder through contactTest, sweeps by convex casts");
}
