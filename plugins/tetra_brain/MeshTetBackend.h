#pragma once
// TetraBrain's queries on a triangle engine (backend="embree", "bullet", or
// any engine a plugin registers): the mesh's boundary faces as one block
// (BoundarySurface) handed to the engine. A deforming mesh has its boundary
// nodes copied in place every frame and the engine's tree refitted, and
// rebuilt once the nodes may have moved more than half an average boundary
// edge since it was built (RefitPolicy). A contact presses on the three
// nodes of the triangle the engine names: nearest the burr's centre for a
// sphere, nearest the deepest shell point for a shell it takes point by
// point (a capsule on Embree), nearest the solid for one it takes through
// the tool's solid (Bullet). Every tool shape is taken. The scale
// of the engine's sphere queries is the brain's: a proxy rests contactDepth
// deep, sweeps sample every half average edge, and a displayed burr ten
// contact depths in overlaps (as on the native back-end).
#include <memory>

#include "framework/geometry/TriangleEngine.h"
#include "plugins/tetra_brain/MeshTetRules.h"
#include "plugins/tetra_brain/TetBackend.h"

namespace trephine::tetra {

class MeshTetBackend final : public TetBackend {
 public:
  explicit MeshTetBackend(std::unique_ptr<TriangleEngine> engine);

  void bind(const TetData& data) override;
  void reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) override;
  size_t siteCapacity() const override { return 1; }
  void moveNodes(const NodeFrame& frame) override;
  TetContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites,
                     int32_t& searchStart) override;
  size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override;
  SweepResult sweep(const SweepQuery& query) const override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  std::string owner() const;  // for messages: backend="NAME" of TetraBrain
  SphereQueryScale scale() const;

  std::unique_ptr<TriangleEngine> m_engine;
  TetData m_data;
  BoundarySurface m_surface;
  RefitPolicy m_refit;
  FollowTiming m_following;
  ContactSite m_site;  // the last contact's
};

}  // namespace trephine::tetra
