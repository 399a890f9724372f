// Rigid skulls as CT density voxels: collision, drilling.
#include "framework/core/Registry.h"
#include "plugins/voxel_skull/NativeVoxelBackend.h"
#include "plugins/voxel_skull/VoxelSkull.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::voxel::VoxelSkull>(
      "VoxelSkull", "Rigid skull of CT density voxels: pointshell collision, sweeps and drilling");
  registrar.addBackend<trephine::voxel::NativeVoxelBackend>(
      "VoxelSkull", "native", "The thesis's voxel method: pointshell against voxels or the smooth isosurface");
}
