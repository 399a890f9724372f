#pragma once
// VoxelSkull's queries on a triangle engine (backend="embree", "bullet", or
// any engine a plugin registers): the isosurface of the interpolated density
// (framework/data/IsoSurface.h, marching tetrahedra in blocks of 16^3 cells)
// handed to the engine, and re-extracted block by block where the drill
// lowers the codes. The scale of the engine's sphere queries is the voxel's:
// a proxy rests a tenth of the smallest voxel side deep, sweeps sample every
// half voxel, and a displayed burr pulled one voxel in that still reaches
// the bone overlaps it.
//
// Where the drilled blocks are rebuilt:
//  - alone, in the haptic frame that cut them (dataChanged): the frame pays
//    the re-extraction, the library's rebuild of the blocks and its update
//    over every block, milliseconds on a CT;
//  - with a SkullSurfaceRebuild, on that component's thread: the back-end
//    keeps two copies of the surface (each its own triangles and its own
//    engine, the same library), the haptic loop queries one while the other
//    is brought up to date from the rebuild's own copy of the codes, and the
//    loop adopts the newer copy at the start of a frame (adoptSurface). The
//    surface the tools meet then lags the drill by up to one rebuild period.
#include <array>
#include <memory>
#include <span>
#include <vector>

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
  // Rebuilds the blocks the cut changed, in this frame; nothing once a second
  // copy is kept (the rebuild's thread follows the codes' edits instead).
  void dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) override;
  void adoptSurface(int copy) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  // The rebuild's side (SkullSurfaceRebuild). Init, after bind: makes the
  // second copy (another engine, the same triangles, the tools reserved and
  // described so far and from now on in both); from then on the haptic frame
  // rebuilds nothing.
  void keepSecondCopy();
  bool keepsSecondCopy() const { return m_copies[1].engine != nullptr; }
  const BlockedIsoSurface& surface(int copy) const { return m_copies[size_t(copy)].surface; }
  // On the rebuild's thread, for a copy the haptic loop does not query:
  // re-extracts `blocks` of copy `copy` from `grid` (the rebuild's own codes)
  // and rebuilds them in its engine. Allocates.
  void rebuildCopy(int copy, const VoxelGrid& grid, const CellsWithoutSurface& skip, std::span<const size_t> blocks);

 private:
  std::string owner() const;  // for messages: backend="NAME"
  SphereQueryScale scale() const;
  TriangleEngine& engine() const { return *m_copies[size_t(m_current)].engine; }

  struct Copy {
    BlockedIsoSurface surface;
    std::unique_ptr<TriangleEngine> engine;
  };
  struct DescribedTool {
    std::span<const ShellPoint> shell;
    ToolSolid solid;
  };
  std::array<Copy, 2> m_copies;
  int m_current = 0;  // the copy the haptic loop queries
  VoxelData m_data;
  // What the tools told the first engine, for the second one.
  std::vector<std::span<const ShellPoint>> m_shells;
  std::vector<DescribedTool> m_tools;
};

}  // namespace trephine::voxel
