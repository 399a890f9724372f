#pragma once
// VoxelSkull's queries on a triangle engine (backend="embree", "bullet", or
// any engine a plugin registers): the isosurface of the interpolated density
// (framework/data/IsoSurface.h, marching tetrahedra in blocks of 16^3 cells)
// handed to the engine, and re-extracted block by block where the drill
// lowers the codes. The scale of the engine's sphere queries is the voxel's:
// a proxy rests a tenth of the smallest voxel side deep, sweeps sample every
// half voxel, and a displayed burr pulled one voxel in that still reaches
// the bone overlaps it.
#include <memory>

#include "framework/data/IsoSurface.h"
#include "framework/geometry/TriangleEngine.h"
#include "plugins/voxel_skull/VoxelBackend.h"

namespace trephine::voxel {

class MeshVoxelBackend final : public VoxelBackend {
 public:
  explicit MeshVoxelBackend(std::unique_ptr<TriangleEngine> engine);

  void bind(const VoxelData& data) override;
  void reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) override;
  VoxelContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool touchedVoxels) override;
  size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override;
  SweepResult sweep(const SweepQuery& query) const override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  void dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  std::string owner() const;  // for messages: backend="NAME"
  SphereQueryScale scale() const;

  std::unique_ptr<TriangleEngine> m_engine;
  VoxelData m_data;
  BlockedIsoSurface m_surface;
};

}  // namespace trephine::voxel
