#pragma once
// VoxelSkull's queries on Embree (backend="embree"): the isosurface of the
// interpolated density (IsoSurface.h, the native smooth surface) as
// triangles, one Embree geometry per block of cells, so a drilled region is
// re-extracted and rebuilt block by block.
//  - A spherical tool (every shell point at one radius from its centre) is
//    treated as the exact sphere: the closest point of the surface to the
//    centre (rtcPointQuery) gives the distance d; the centre is inside the
//    bone when a ray from it crosses the surface an odd number of times;
//    penetration r - d outside, r + d inside. The normal outside is the mean
//    of the face normals of the triangles within r, weighted by depth and
//    area: the closest point's own direction jumps from face to face at a
//    crease, and a proxy lifted along it chatters. Inside, from the centre
//    out through the closest point.
//  - Other shells go point by point: inside by ray parity, depth to the
//    closest point, normals weighted by depth, the deepest along the contact
//    normal (as the native deepest-point variant).
//  - Sweeps sample the sphere's exact depth every half voxel along the path
//    and refine the first sample that is too deep by bisection (to 1e-4 mm):
//    a free sphere stops where it touches; one resting in its skin may sink
//    one skin deeper than it is (or than one skin) and slides.
// Embree's types stay in the .cpp (the state behind a pointer).
#include <memory>

#include "plugins/voxel_skull/VoxelBackend.h"

namespace trephine::embree {

class EmbreeVoxelBackend final : public voxel::VoxelBackend {
 public:
  EmbreeVoxelBackend();
  ~EmbreeVoxelBackend() override;

  void bind(const voxel::VoxelData& data) override;
  void reserveShell(std::span<const ShellPoint> shell) override;
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

}  // namespace trephine::embree
