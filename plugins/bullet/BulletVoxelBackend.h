#pragma once
// VoxelSkull's queries on Bullet (backend="bullet"): the isosurface of the
// interpolated density (IsoSurface.h, as the embree back-end meshes it), one
// btBvhTriangleMeshShape per block of cells, each its own object in a Bullet
// collision world (its broadphase a dynamic AABB tree), so a drilled region
// is re-extracted and rebuilt block by block.
//  - The burr is a Bullet sphere (btSphereShape) of the shell's radius: a
//    spherical shell only; another shell (CapsuleTool) is refused when the
//    scene loads. contactTest gives one contact per triangle the sphere
//    reaches (Bullet's sphere-triangle detector); the closest point of each
//    to the centre gives the penetration, r - d, and the normal is the mean
//    of their face normals weighted by depth and area (as the embree
//    back-end: continuous across creases). A centre behind the closest triangle is
//    inside: r + d, the normal out through the closest point.
//  - Sweeps are Bullet convex casts (convexSweepTest) of the sphere shrunk
//    by the depth the proxy may keep: a free sphere stops where it touches,
//    one resting in its skin slides (the same rule as the embree back-end).
//  - Rays: rayTest. Overlap: the centre behind the surface, or the sphere
//    pulled one voxel in still touching.
// Bullet's types stay in the .cpp (the state behind a pointer). What Bullet
// allocates per query is measured by BulletBackendTest.
#include <memory>

#include "plugins/voxel_skull/VoxelBackend.h"

namespace trephine::bullet {

class BulletVoxelBackend final : public voxel::VoxelBackend {
 public:
  BulletVoxelBackend();
  ~BulletVoxelBackend() override;

  void bind(const voxel::VoxelData& data) override;
  void reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) override;
  voxel::VoxelContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool touchedVoxels) override;
  size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override;
  SweepResult sweep(const SweepQuery& query) const override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  void dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  struct State;
  std::unique_ptr<State> m_state;
};

}  // namespace trephine::bullet
