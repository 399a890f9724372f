#pragma once
// The queries VoxelSkull hands to its collision back-end (the `backend`
// field): contact of a pointshell, sweeps, the overlap of a displayed proxy
// and ray casts, on the data VoxelSkull keeps and drills. A back-end reads
// the data and never changes it; the drilling between two queries is VoxelSkull's.
#include <array>
#include <cstdint>
#include <optional>
#include <span>

#include "framework/core/CollisionBackend.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/data/DensityVolume.h"
#include "plugins/voxel_skull/SolidGrid.h"

namespace trephine::voxel {

// The skull's data, owned by VoxelSkull, at fixed addresses for the run.
struct VoxelData {
  const DensityVolume* volume = nullptr;
  const SolidGrid* grid = nullptr;  // its codes fall as the skull is drilled
  bool algorithm1 = false;          // penetration by McNeely tangent planes (Algorithm 1), else the deepest point
};

// A contact, and when asked for, the voxels the thesis's removal law cuts for
// it (each once): the colliding voxels on the voxel surface, the 8 voxel
// centres around each colliding point on the smooth one. `touched` is valid
// until the back-end's next query.
struct VoxelContact {
  ShellContact contact;
  std::span<const int64_t> touched;
};

class VoxelBackend : public CollisionBackend {
 public:
  // At init, and again whenever the data is replaced.
  virtual void bind(const VoxelData& data) = 0;
  virtual void reserveShell(std::span<const ShellPoint> shell) = 0;
  // The solid a reserved shell samples (ShellContactTarget::describeTool);
  // may throw when the back-end cannot take the tool.
  virtual void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
    (void)shell;
    (void)solid;
  }
  virtual VoxelContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool touchedVoxels) = 0;
  // The broad phase of collide() alone, for timing it apart (studies): the
  // candidates the narrow phase would examine (native: the shell points in
  // bone; mesh back-ends: the triangles within the tool's reach).
  virtual size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) = 0;
  virtual SweepResult sweep(const SweepQuery& query) const = 0;
  virtual bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const = 0;
  virtual std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const = 0;
  // The codes of the voxel box [first, last] (inclusive indices) were lowered
  // (drilling): a back-end with its own copy of the surface updates it there.
  virtual void dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
    (void)first;
    (void)last;
  }
  // The haptic loop's queries go to copy `copy` of the back-end's surface
  // from now on (a back-end that keeps two, one brought up to date on
  // another thread: MeshVoxelBackend). At the start of a frame.
  virtual void adoptSurface(int copy) { (void)copy; }
};

}  // namespace trephine::voxel
