// Rigid skulls as CT density voxels: collision, drilling.
#include <sstream>

#include "framework/core/Registry.h"
#include "plugins/voxel_skull/MeshVoxelBackend.h"
#include "plugins/voxel_skull/NativeVoxelBackend.h"
#include "plugins/voxel_skull/Phantoms.h"
#include "plugins/voxel_skull/SkullSurfaceRebuild.h"
#include "plugins/voxel_skull/VoxelSkull.h"
#include "framework/formats/volume/DicomWriter.h"
#include "framework/formats/volume/VolumeWriter.h"

TREPHINE_PLUGIN_ENTRY(registrar) {
  registrar.add<trephine::voxel::VoxelSkull>(
      "VoxelSkull", "Rigid skull of CT density voxels: pointshell collision, sweeps and drilling");
  registrar.addBackend<trephine::voxel::NativeVoxelBackend>(
      "VoxelSkull", "native", "The thesis's voxel method: pointshell against voxels or the smooth isosurface");
  registrar.add<trephine::voxel::SkullSurfaceRebuild>(
      "SkullSurfaceRebuild",
      "Rebuilds a drilled skull's surface for a mesh back-end (embree, bullet) off the haptic thread, in a second "
      "copy the haptic loop adopts");
  // Every triangle engine (embree, bullet) is a back-end too, on the smooth isosurface.
  registrar.addEngineAdapter("VoxelSkull", [](std::unique_ptr<trephine::CollisionBackend> engine) {
    return trephine::adaptEngine<trephine::voxel::MeshVoxelBackend>(std::move(engine));
  });
  registrar.addPhantomWriter({.kind = "volume",
                              .suffixes = {".mha", ".mhd"},
                              .plugin = {},
                              .help = trephine::voxel::phantomHelp(),
                              .canWriteRaw = true,
                              .write = [](const std::string& specification, const std::string& file, bool raw) {
                                const trephine::DensityVolume volume =
                                    trephine::voxel::makePhantom(specification);
                                trephine::formats::writeMetaImage(volume, file, !raw);
                                const auto& d = volume.dims();
                                std::ostringstream description;
                                description << d[0] << " x " << d[1] << " x " << d[2] << " voxels of "
                                            << volume.spacing().x() << " mm, densities " << volume.minDensity()
                                            << " to " << volume.maxDensity();
                                return description.str();
                              }});
  registrar.addPhantomWriter({.kind = "DICOM CT series (a new directory)",
                              .suffixes = {"/"},
                              .plugin = {},
                              .help = "  (the volume phantoms above, e.g. head?voxel=1.0)\n",
                              .canWriteRaw = false,
                              .write = [](const std::string& specification, const std::string& directory, bool) {
                                const trephine::DensityVolume volume =
                                    trephine::voxel::makePhantom(specification);
                                trephine::formats::writeDicomSeries(volume, directory, "phantom:" + specification);
                                std::ostringstream description;
                                description << volume.dims()[2] << " slices of " << volume.dims()[0] << " x "
                                            << volume.dims()[1] << ", " << volume.spacing().x()
                                            << " mm voxels, values " << volume.minDensity() << " to "
                                            << volume.maxDensity();
                                return description.str();
                              }});
}
