#pragma once
// A closed triangle surface in a Bullet collision world, block by block
// (TriangleBlocks): each block a btBvhTriangleMeshShape reading the block's
// own arrays (double precision), its own object, so a block whose triangles
// change (drilling) is rebuilt alone and a block whose vertices move
// (deformation) is refitted alone. The library side of BulletEngine, with
// the queries a spherical burr needs:
//  - contact: Bullet's trees (the dynamic AABB tree over the blocks, each
//    block's BVH) find the triangles whose boxes meet the burr's, the exact
//    distance of each is computed here;
//    inside: behind the closest triangle's face, or by ray parity at an edge
//    or a vertex and beyond the radius;
//  - sweeps: Bullet's convex cast of the sphere shrunk by the depth the proxy
//    may keep, against the triangles of the blocks in the swept box that come
//    within its reach (the others are skipped: CulledSphereCast); rays: rayTest.
// Every allocation Bullet makes is counted (btAlignedAllocSetCustom).
// Bullet's types stay in this plugin (this header is not installed).
#include <btBulletCollisionCommon.h>

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "framework/geometry/MeshSphereContact.h"
#include "framework/geometry/MeshSurfaceCounters.h"
#include "framework/geometry/ShellContactTarget.h"
#include "framework/data/TriangleBlocks.h"

namespace trephine {
struct Counter;
}

namespace trephine::bullet {

// The closest point of the surface to a sphere's centre, among the
// triangles Bullet reports within the sphere.
struct ClosestTriangle {
  TriangleRef which;
  double distance = 0;           // mm, centre to the closest point
  Vec3 point = Vec3::Zero();     // mm, on the surface
  int contacts = 0;              // triangles within reach
  Vec3 weighted = Vec3::Zero();  // their face normals times depth and area (summed)
  bool found() const { return which.valid(); }
};

// Installs the counting allocator before the first Bullet object is made.
struct AllocationHook {
  AllocationHook();
};

// A tool's shaft (ToolSolid) as a Bullet cylinder, queried with Bullet's own
// convex-triangle contacts (GJK and EPA): a cylinder of the shaft's radius
// from the burr's centre along its axis, flat at its end as the shell is open.
class BulletShaft {
 public:
  explicit BulletShaft(const ToolSolid& solid);
  double burrRadius() const { return m_burrRadius; }

 private:
  friend class BulletScene;
  AllocationHook m_hook;
  double m_burrRadius = 0;  // mm
  double m_radius = 0;      // mm, the shaft's
  double m_length = 0;      // mm, from the burr's centre
  Vec3 m_axis = Vec3::UnitZ();  // in the tool frame
  btTransform m_local;      // the cylinder's frame in the tool frame
  btCylinderShapeZ m_shape;
  mutable btCollisionObject m_object;
};

class BulletScene {
 public:
  BulletScene();
  ~BulletScene();
  BulletScene(const BulletScene&) = delete;
  BulletScene& operator=(const BulletScene&) = delete;

  // Builds every block of `blocks` (kept by reference: it must outlive the
  // scene). `deformationMargin` (mm): the blocks' vertices will move, by up
  // to this much from where they are at each build (the quantized trees
  // cover their bounds grown by it; 0 for a surface that does not move).
  void build(const TriangleBlocks& blocks, double deformationMargin = 0);
  // The triangles of these blocks changed: rebuilds them. In the haptic
  // loop: a block Bullet cannot take is counted, not thrown.
  void rebuildBlocks(std::span<const size_t> changed);
  // The vertices of a block moved in place (same arrays, same triangles),
  // within the deformation margin of where they were at its last build:
  // refits its BVH; or rebuilds it when `rebuild` (needed before they move
  // farther: the quantized tree cannot hold a box beyond its bounds).
  void moveVertices(size_t index, bool rebuild);
  bool empty() const { return m_blocks.empty(); }
  const TriangleBlocks& blocks() const { return *m_source; }

  ClosestTriangle closest(const Vec3& centre, double radius) const;
  bool inside(const Vec3& p) const;
  // Inside, given the closest point `c` of the surface to `centre` (found).
  bool behindClosest(const Vec3& centre, const ClosestTriangle& c) const;
  size_t trianglesWithin(const Vec3& p, double radius) const;

  // A spherical burr of `radius` centred at X_WT.position; `nearest`: where
  // the surface is nearest the centre.
  ShellContact sphereContact(const Pose& X_WT, std::span<const ShellPoint> shell, double radius,
                             ClosestTriangle* nearest = nullptr) const;
  // The burr and, when `shaft` is given, its shaft: penetration the deeper of
  // the two, the normal their depth-weighted mean. `nearest`: the burr's.
  ShellContact toolContact(const Pose& X_WT, std::span<const ShellPoint> shell, double radius, const BulletShaft* shaft,
                           ClosestTriangle* nearest = nullptr) const;
  // `skin`: how deep a proxy rests (MeshSphereContact.h's sweepAllowance).
  SweepResult sweepSphere(const SweepQuery& query, double radius, double skin) const;
  // Visibly in: the sphere pulled `inset` in still reaches the surface, or the centre is inside.
  bool overlapsSphere(const Vec3& centre, double radius, double inset) const;
  std::optional<SurfaceHit> raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const;

  MeshSurfaceCounters& counts() { return m_counts; }
  void reportCounters(std::vector<Counter>& counters) const;

 private:
  struct Block {
    std::unique_ptr<btTriangleIndexVertexArray> mesh;
    std::unique_ptr<btBvhTriangleMeshShape> shape;
    std::unique_ptr<btCollisionObject> object;
    Box3 treeBounds;  // the quantized tree's bounds: the vertices' at the build, grown by the margin
  };
  void clear();
  void attachBlock(size_t index);
  double farDistance() const;  // mm, a ray this long leaves the surface's bounds

  AllocationHook m_hook;  // first: before any Bullet member allocates
  const TriangleBlocks* m_source = nullptr;
  double m_margin = 0;  // mm, the deformation margin
  Box3 m_bounds;        // of every vertex the surface has had
  btDefaultCollisionConfiguration m_configuration;
  btCollisionDispatcher m_dispatcher{&m_configuration};
  btDbvtBroadphase m_broadphase;
  btCollisionWorld m_world{&m_dispatcher, &m_broadphase, &m_configuration};
  std::vector<Block> m_blocks;          // per block; empty members when it has no triangles
  mutable btSphereShape m_sphere{1.0};  // the burr, its radius set per sweep
  mutable MeshSurfaceCounters m_counts;
  uint64_t m_refits = 0, m_followAllocations = 0, m_followBytes = 0;
  mutable uint64_t m_contactTests = 0, m_casts = 0, m_rays = 0, m_castTriangles = 0, m_culledTriangles = 0;
  mutable uint64_t m_queries = 0, m_queryAllocations = 0, m_queryBytes = 0;  // contact, sweep, overlap
};

// The tools a Bullet back-end was told of: each shell's burr, and its shaft
// when the shell is not a sphere (CapsuleTool).
class BulletTools {
 public:
  struct Tool {
    double radius = 0;                   // mm, the burr's
    const BulletShaft* shaft = nullptr;  // or none: a spherical shell
  };
  // True: the shell is a sphere.
  bool reserve(std::span<const ShellPoint> shell) { return m_shells.add(shell).sphere; }
  // Throws when the shell is not a sphere and the solid has no shaft.
  void describe(std::span<const ShellPoint> shell, const ToolSolid& solid, const std::string& owner);
  // A reserved shell's tool; none for a shell not reserved, or not a sphere
  // and not described.
  std::optional<Tool> find(std::span<const ShellPoint> shell) const;

 private:
  ReservedShells m_shells;
  std::vector<std::pair<const ShellPoint*, std::unique_ptr<BulletShaft>>> m_shafts;
};

}  // namespace trephine::bullet
