#pragma once
// The triangle engine on Embree (backend="embree" for any target that keeps
// its surface as triangles: the skull's isosurface, the brain's boundary).
// One BVH per block, instanced in a top scene (EmbreeScene).
//  - A spherical shell is the exact sphere: the closest point of the surface
//    to its centre (rtcPointQuery) gives the distance d, the centre is inside
//    when a ray from it crosses the surface an odd number of times;
//    penetration r - d outside, r + d inside; the normal the depth- and
//    area-weighted mean of the face normals within reach (continuous across
//    creases), inside the way out through the closest point.
//  - Any other shell point by point: inside by ray parity, depth to the
//    closest point, normals weighted by depth, the deepest along the contact
//    normal (as the native deepest-point variant); no nearest triangle.
//  - Sweeps sample the sphere's exact depth along the path (the target's
//    sweep step) and refine the first sample too deep by bisection.
// Embree's types stay in the .cpp (the state behind a pointer).
#include <memory>

#include "framework/geometry/TriangleEngine.h"

namespace trephine::embree {

class EmbreeEngine final : public TriangleEngine {
 public:
  EmbreeEngine();
  ~EmbreeEngine() override;

  std::string_view name() const override { return "embree"; }
  std::unique_ptr<TriangleEngine> another() const override { return std::make_unique<EmbreeEngine>(); }
  void build(const TriangleBlocks& blocks, double deformationMargin) override;
  void rebuildBlocks(std::span<const size_t> changed) override;
  void moveVertices(size_t block, bool rebuild) override;
  bool empty() const override;
  MeshSurfaceCounters& counts() override;
  ShellSupport reserveShell(std::span<const ShellPoint> shell) override;
  void describeTool(std::span<const ShellPoint>, const ToolSolid&, const std::string&) override {}
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

}  // namespace trephine::embree
