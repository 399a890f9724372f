#pragma once
// TetraBrain's queries on Bullet (backend="bullet"): the mesh's boundary
// faces as one btBvhTriangleMeshShape reading the boundary's own vertex array
// (BoundarySurface) in a BulletScene, the burr as a btSphereShape of its
// shell's radius (a spherical shell only; another is refused when the scene
// loads). A deforming mesh refits the quantized tree from the node positions
// every frame (refitTree), and rebuilds it once the nodes may have moved more
// than half an average boundary edge since it was built (RefitPolicy). A
// contact presses on the three nodes of the triangle closest to the burr's centre.
#include <memory>

#include "plugins/tetra_brain/TetBackend.h"

namespace trephine::bullet {

class BulletTetBackend final : public tetra::TetBackend {
 public:
  BulletTetBackend();
  ~BulletTetBackend() override;

  void bind(const tetra::TetData& data) override;
  void reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) override;
  size_t siteCapacity() const override { return 1; }
  void moveNodes(const tetra::NodeFrame& frame) override;
  tetra::TetContact collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites) override;
  size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) override;
  SweepResult sweep(const SweepQuery& query) const override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  struct State;
  std::unique_ptr<State> m_state;
};

}  // namespace trephine::bullet
