#pragma once
// A closed triangle surface in Embree, block by block (TriangleBlocks): one
// BVH per block, instanced in a top scene under the block's index, so a
// block whose triangles change (drilling) is rebuilt alone, and a block
// whose vertices move (deformation) is refitted alone. The library side of
// EmbreeEngine, with the queries a spherical burr needs:
//  - contact: the closest point of the surface to the centre
//    (rtcPointQuery) gives the distance d; the centre is inside when a ray
//    from it crosses the surface an odd number of times; penetration r - d
//    outside, r + d inside, the normal by the shared rules (MeshSphereContact.h);
//  - sweeps: the sphere's exact depth sampled along the path and the first
//    sample too deep refined by bisection (to 1e-4 mm);
//  - overlap and ray casts.
// Embree's types stay in this plugin (this header is not installed).
#include <embree3/rtcore.h>

#include <optional>
#include <span>
#include <vector>

#include "framework/geometry/MeshSurfaceCounters.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/data/TriangleBlocks.h"
#include "framework/geometry/TriangleEngine.h"

namespace trephine {
struct Counter;
}

namespace trephine::embree {

class EmbreeScene {
 public:
  EmbreeScene() = default;
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  ~EmbreeScene();

  // Builds every block of `blocks` (kept by reference for the queries: it
  // must outlive the scene). `deforming`: the blocks' vertices will move and
  // be refitted. Throws when Embree fails.
  void build(const TriangleBlocks& blocks, bool deforming);
  // The triangles of these blocks changed: rebuilds them and the top level.
  // In the haptic loop: a block Embree cannot take is counted, not thrown.
  void rebuildBlocks(std::span<const size_t> changed);
  // The vertices of a block moved (same triangles): refits its BVH, or
  // rebuilds it when `rebuild` (a refitted tree keeps its topology, and its
  // boxes overlap more the farther the vertices move); then the top level.
  void moveVertices(size_t index, bool rebuild);
  bool empty() const { return m_scene == nullptr; }
  const TriangleBlocks& blocks() const { return *m_blocks; }

  // The closest surface point within `radius` of p. `averaged`: also the sum
  // of the face normals of the triangles within `radius`, weighted by depth
  // and area; `which`: the closest point's triangle.
  bool closest(const Vec3& p, double radius, Vec3& point, double& distance, Vec3* averaged = nullptr,
               TriangleRef* which = nullptr) const;
  // The first crossing of the ray from `origin` along unit `direction`
  // between `near` and `far` (mm): its distance, or a negative value.
  double firstHit(const Vec3& origin, const Vec3& direction, double near, double far, TriangleRef& hit) const;
  // Inside the closed surface: an odd number of crossings along a fixed ray.
  bool inside(const Vec3& p) const;
  // The broad phase alone: the triangles whose boxes reach within `radius` of p.
  size_t trianglesWithin(const Vec3& p, double radius) const;

  // A spherical burr of `radius` centred at X_WT.position; `closestTriangle`
  // and `closestPoint`: where the surface is nearest the centre.
  ShellContact sphereContact(const Pose& X_WT, std::span<const ShellPoint> shell, double radius,
                             TriangleRef* closestTriangle = nullptr, Vec3* closestPoint = nullptr) const;
  SweepResult sweepSphere(const SweepQuery& query, double radius, const SphereQueryScale& scale) const;
  bool overlapsSphere(const Vec3& centre, double radius, const SphereQueryScale& scale) const;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const;

  MeshSurfaceCounters& counts() { return m_counts; }
  // A contact found outside sphereContact (a shell point by point).
  void countContactFrame() const { ++m_counts.contactFrames; }
  void reportCounters(std::vector<Counter>& counters) const;

 private:
  struct Block {
    RTCScene scene = nullptr;
    RTCGeometry triangles = nullptr;  // kept for the refits of a deforming block
    RTCGeometry instance = nullptr;
    float* vertices = nullptr;  // Embree's vertex buffer (x, y, z per vertex)
  };
  void release();
  bool attachBlock(size_t index);
  void detachBlock(size_t index);
  void copyVertices(size_t index);

  const TriangleBlocks* m_blocks = nullptr;
  bool m_deforming = false;
  RTCDevice m_device = nullptr;
  RTCScene m_scene = nullptr;  // the top scene: one instance per block with triangles
  std::vector<Block> m_blockScenes;
  mutable MeshSurfaceCounters m_counts;
  mutable uint64_t m_rays = 0, m_pointQueries = 0;
  uint64_t m_refits = 0;
};

}  // namespace trephine::embree
