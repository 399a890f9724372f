#pragma once
// The triangle engine on Bullet (backend="bullet" for any target that keeps
// its surface as triangles: the skull's isosurface, the brain's boundary):
// one btBvhTriangleMeshShape per block, each its own object in a Bullet
// collision world (its broadphase a dynamic AABB tree), refitted or rebuilt
// block by block (BulletScene).
//  - The burr is a Bullet sphere (btSphereShape) of the shell's radius;
//    contactTest gives one contact per triangle the sphere reaches (Bullet's
//    sphere-triangle detector); the closest point of each to the centre
//    gives the penetration, r - d, and the normal is the mean of their face
//    normals weighted by depth and area (continuous across creases). A
//    centre behind the closest triangle is inside: r + d, the normal out
//    through the closest point.
//  - A shell that is not a sphere needs the solid its tool describes: a burr
//    on a shaft (CapsuleTool), the shaft a Bullet cylinder queried with
//    Bullet's own convex-triangle contacts (GJK and EPA); any other is refused.
//  - Sweeps are Bullet convex casts (convexSweepTest) of the sphere shrunk
//    by the depth the proxy may keep; rays: rayTest.
// Bullet's types stay in the .cpp (the state behind a pointer). What Bullet
// allocates per query is counted (BulletBackendTest measures it).
#include <memory>

#include "framework/geometry/TriangleEngine.h"

namespace trephine::bullet {

class BulletEngine final : public TriangleEngine {
 public:
  BulletEngine();
  ~BulletEngine() override;

  std::string_view name() const override { return "bullet"; }
  std::unique_ptr<TriangleEngine> another() const override { return std::make_unique<BulletEngine>(); }
  void build(const TriangleBlocks& blocks, double deformationMargin) override;
  void rebuildBlocks(std::span<const size_t> changed) override;
  void moveVertices(size_t block, bool rebuild) override;
  bool empty() const override;
  MeshSurfaceCounters& counts() override;
  ShellSupport reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid, const std::string& owner) override;
  TriangleContact contact(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  size_t broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) const override;
  SweepResult sweep(const SweepQuery& query, const SphereQueryScale& scale) const override;
  bool overlaps(const Pose& X_WT, std::span<const ShellPoint> shell, const SphereQueryScale& scale) const override;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  struct State;
  std::unique_ptr<State> m_state;
};

}  // namespace trephine::bullet
