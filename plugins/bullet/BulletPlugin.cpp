// Collision back-ends on Bullet's collision world.
#include "framework/core/Registry.h"
#include "plugins/bullet/BulletTetBackend.h"
#include "plugins/bullet/BulletVoxelBackend.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.addBackend<trephine::bullet::BulletVoxelBackend>(
      "VoxelSkull", "bullet",
      "The skull's isosurface as Bullet triangle meshes (btBvhTriangleMeshShape per block): the burr as a Bullet "
      "sphere and a shaft as a Bullet cylinder through contactTest, sweeps by convex casts");
  registrar.addBackend<trephine::bullet::BulletTetBackend>(
      "TetraBrain", "bullet",
      "The brain's boundary faces as a Bullet triangle mesh (btBvhTriangleMeshShape), refitted to the node "
      "positions every frame: the burr as a Bullet sphere and a shaft as a Bullet cylinder through contactTest, sweeps "
      "by convex casts");
}
