#pragma once
// The hand-over between a SkullSurfaceRebuild (on its own thread) and the
// VoxelSkull whose mesh back-end keeps two copies of the surface: the rebuild
// publishes which copy it brought up to date, the skull's haptic loop adopts
// it at the start of a frame and publishes back the copy it now queries, so
// the rebuild touches only the other one.
#include <cstdint>

namespace trephine::voxel {

// Channel names: the rebuild's, and the skull's answer.
inline constexpr const char* kSurfaceReadyChannel = "surface_ready";
inline constexpr const char* kSurfaceInUseChannel = "surface_in_use";

struct SurfaceCopy {
  uint64_t version = 0;  // 0: the copy the back-end built at init
  int copy = 0;          // 0 or 1
};

}  // namespace trephine::voxel
