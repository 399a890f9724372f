#include "plugins/bullet/BulletVoxelBackend.h"

#include <btBulletCollisionCommon.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>

#include "framework/geometry/ClosestPoint.h"
#include "plugins/voxel_skull/IsoSurface.h"
#include "plugins/voxel_skull/MeshSphereContact.h"
#include "plugins/voxel_skull/MeshSurfaceCounters.h"

namespace trephine::bullet {

namespace {

constexpr double kSweepTolerance = 1e-4;  // mm, as the other back-ends
const Vec3 kParityDirection = Vec3(0.5403, 0.5871, 0.6029).normalized();

// Every allocation Bullet makes goes through btAlignedAlloc: counted here, so
// that the back-end reports what its queries allocate in the haptic loop.
std::atomic<uint64_t> g_bulletAllocations{0};
std::atomic<uint64_t> g_bulletBytes{0};
void* countingAlloc(size_t size) {
  g_bulletAllocations.fetch_add(1, std::memory_order_relaxed);
  g_bulletBytes.fetch_add(size, std::memory_order_relaxed);
  void* memory = std::malloc(size);
  if (!memory) throw std::bad_alloc();  // Bullet would use the null pointer: fail where it can be caught
  return memory;
}
void countingFree(void* memory) { std::free(memory); }

// Installed before the first Bullet object of a back-end is made (malloc and
// free underneath, as Bullet's own default, so earlier blocks free alike).
struct AllocationHook {
  AllocationHook() { btAlignedAllocSetCustom(countingAlloc, countingFree); }
};

// Allocations by Bullet during one query.
struct QueryAllocations {
  uint64_t& total;
  uint64_t& bytes;
  const uint64_t startCount = g_bulletAllocations.load(std::memory_order_relaxed);
  const uint64_t startBytes = g_bulletBytes.load(std::memory_order_relaxed);
  ~QueryAllocations() {
    total += g_bulletAllocations.load(std::memory_order_relaxed) - startCount;
    bytes += g_bulletBytes.load(std::memory_order_relaxed) - startBytes;
  }
};

btVector3 toBullet(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 fromBullet(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
btTransform at(const Vec3& p) { return btTransform(btQuaternion::getIdentity(), toBullet(p)); }

// A triangle's share of the contact normal: its face normal (out of the
// bone) times its area (half the cross product), so that the mean does not
// lean towards where the surface happens to be cut into more triangles; the
// caller weights it by depth.
Vec3 areaNormal(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a); }

// The closest point of the surface to the sphere's centre among the
// contacts Bullet reports (one per triangle within reach).
struct ClosestContact final : btCollisionWorld::ContactResultCallback {
  const btCollisionObject* tool = nullptr;
  const voxel::BlockedIsoSurface* surface = nullptr;
  Vec3 centre = Vec3::Zero();
  double distance = std::numeric_limits<double>::infinity();  // mm, centre to the closest point
  Vec3 point = Vec3::Zero();                                  // mm, on the surface
  int block = -1, triangle = -1;
  int contacts = 0;
  double reach = 0;              // mm, the sphere's radius
  Vec3 weighted = Vec3::Zero();  // sum of the reached triangles' face normals times depth and area

  btScalar addSingleResult(btManifoldPoint&, const btCollisionObjectWrapper* a, int, int indexA,
                           const btCollisionObjectWrapper* b, int, int indexB) override {
    // Bullet found the triangle; its closest point to the centre is computed
    // here (Bullet's contact points of a sphere are on the sphere or the
    // triangle depending on which object it takes first).
    const bool toolIsA = a->getCollisionObject() == tool;
    const btCollisionObject* mesh = toolIsA ? b->getCollisionObject() : a->getCollisionObject();
    const int meshBlock = mesh->getUserIndex();
    const int meshTriangle = toolIsA ? indexB : indexA;
    const voxel::TriangleMesh& triangles = surface->block(size_t(meshBlock));
    const auto& t = triangles.triangles[size_t(meshTriangle)];
    const Vec3 &v0 = triangles.vertices[size_t(t[0])], &v1 = triangles.vertices[size_t(t[1])],
               &v2 = triangles.vertices[size_t(t[2])];
    const Vec3 onMesh = closestOnTriangle(centre, v0, v1, v2);
    ++contacts;
    const double d = (onMesh - centre).norm();
    if (d < reach) weighted += areaNormal(v0, v1, v2) * (reach - d);
    if (d < distance) {
      distance = d;
      point = onMesh;
      block = meshBlock;
      triangle = meshTriangle;
    }
    return 0;
  }
};

// Counts the surface crossings along a ray (parity: inside the bone when odd).
// A ray through an edge or a vertex hits every triangle there at the same
// distance: hits closer than 1e-9 of the ray's length are one crossing.
struct CrossingCount final : btCollisionWorld::RayResultCallback {
  static constexpr int kMaxHits = 256;
  std::array<double, kMaxHits> fractions{};
  int hits = 0;
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result, bool) override {
    if (hits < kMaxHits) fractions[size_t(hits++)] = result.m_hitFraction;
    return m_closestHitFraction;  // keep going: every hit
  }
  int crossings() {
    std::sort(fractions.begin(), fractions.begin() + hits);
    int distinct = 0;
    for (int i = 0; i < hits; ++i) distinct += i == 0 || fractions[size_t(i)] - fractions[size_t(i - 1)] > 1e-9;
    return distinct;
  }
};

// The first hit along a ray, with its block and triangle.
struct FirstHit final : btCollisionWorld::RayResultCallback {
  int block = -1, triangle = -1;
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result, bool) override {
    if (result.m_hitFraction < m_closestHitFraction) {
      m_closestHitFraction = result.m_hitFraction;
      m_collisionObject = result.m_collisionObject;
      block = result.m_collisionObject->getUserIndex();
      triangle = result.m_localShapeInfo ? result.m_localShapeInfo->m_triangleIndex : -1;
    }
    return m_closestHitFraction;
  }
};

// The broad phase alone: the blocks whose boxes meet the tool's (Bullet's
// dynamic AABB tree), then the triangles of each whose boxes do (its BVH).
struct TriangleCount final : btTriangleCallback {
  size_t triangles = 0;
  void processTriangle(btVector3*, int, int) override { ++triangles; }
};
struct BlockTriangles final : btBroadphaseAabbCallback {
  btVector3 min, max;
  TriangleCount count;
  bool process(const btBroadphaseProxy* proxy) override {
    const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    static_cast<const btConcaveShape*>(object->getCollisionShape())->processAllTriangles(&count, min, max);
    return true;
  }
};

}  // namespace

struct BulletVoxelBackend::State {
  AllocationHook hook;  // first: before any Bullet member allocates
  voxel::VoxelData data;
  voxel::BlockedIsoSurface surface;
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};
  // Per block with triangles: its mesh (pointing into the surface's arrays), shape and object.
  struct Block {
    std::unique_ptr<btTriangleIndexVertexArray> mesh;
    std::unique_ptr<btBvhTriangleMeshShape> shape;
    std::unique_ptr<btCollisionObject> object;
  };
  std::vector<Block> blocks;
  mutable btSphereShape sphere{1.0};  // the burr, its radius set per query
  mutable btCollisionObject tool;
  struct Shell {
    const ShellPoint* source = nullptr;
    size_t size = 0;
    double radius = 0;  // mm
  };
  std::vector<Shell> shells;
  voxel::MeshSurfaceCounters counts;
  mutable uint64_t contactTests = 0, casts = 0, rays = 0;
  mutable uint64_t queries = 0, queryAllocations = 0, queryBytes = 0;  // collide, sweep, overlaps

  State() { tool.setCollisionShape(&sphere); }
  ~State() { clear(); }

  void clear() {
    for (Block& b : blocks)
      if (b.object) world.removeCollisionObject(b.object.get());
    blocks.clear();
  }

  const Shell* findShell(std::span<const ShellPoint> shell) const {
    for (const Shell& s : shells)
      if (s.source == shell.data() && s.size == shell.size()) return &s;
    return nullptr;
  }

  // (Re)builds the Bullet mesh of block `index` from the surface's triangles.
  void attachBlock(size_t index) {
    Block& b = blocks[index];
    if (b.object) world.removeCollisionObject(b.object.get());
    b = Block{};
    const voxel::TriangleMesh& mesh = surface.block(index);
    if (mesh.triangles.empty()) return;
    // Bullet reads the surface's own arrays: int triples, and (double
    // precision) btScalar triples with Eigen's layout.
    static_assert(sizeof(Vec3) == 3 * sizeof(btScalar));
    b.mesh = std::make_unique<btTriangleIndexVertexArray>(
        int(mesh.triangles.size()), const_cast<int*>(mesh.triangles.front().data()), int(3 * sizeof(int32_t)),
        int(mesh.vertices.size()), const_cast<btScalar*>(mesh.vertices.front().data()), int(sizeof(Vec3)));
    b.shape = std::make_unique<btBvhTriangleMeshShape>(b.mesh.get(), true, true);
    b.shape->setMargin(0);  // the triangles themselves, not a shell around them
    b.object = std::make_unique<btCollisionObject>();
    b.object->setCollisionShape(b.shape.get());
    b.object->setUserIndex(int(index));
    world.addCollisionObject(b.object.get());
  }

  // The closest surface point within `radius` of `centre`, by a Bullet contact test.
  ClosestContact closest(const Vec3& centre, double radius) const {
    ClosestContact c;
    c.tool = &tool;
    c.surface = &surface;
    c.centre = centre;
    c.reach = radius;
    sphere.setUnscaledRadius(radius);
    tool.setWorldTransform(at(centre));
    const_cast<btCollisionWorld&>(world).contactTest(&tool, c);
    ++contactTests;
    return c;
  }

  Vec3 faceNormal(int block, int triangle) const {
    const voxel::TriangleMesh& mesh = surface.block(size_t(block));
    const auto& t = mesh.triangles[size_t(triangle)];
    const Vec3& a = mesh.vertices[size_t(t[0])];
    return (mesh.vertices[size_t(t[1])] - a).cross(mesh.vertices[size_t(t[2])] - a).normalized();
  }

  // Whether `centre` is in the bone, given its closest surface point on
  // (block, triangle): behind that triangle when the point is inside its face
  // (the direction is along the face normal); at an edge or a vertex the
  // faces there disagree, so a ray decides.
  bool behindClosest(const Vec3& centre, const ClosestContact& c) const {
    const Vec3 n = faceNormal(c.block, c.triangle);
    const double along = (centre - c.point).dot(n) / c.distance;
    return std::abs(along) > 0.999 ? along < 0 : inside(centre);
  }

  bool inside(const Vec3& p) const {
    CrossingCount count;
    const double far = 2.0 * data.volume->bounds().diagonal().norm() + 10.0;  // mm: out of the volume
    world.rayTest(toBullet(p), toBullet(p + far * kParityDirection), count);
    ++rays;
    return count.crossings() % 2 == 1;
  }
};

BulletVoxelBackend::BulletVoxelBackend() : m_state(std::make_unique<State>()) {}
BulletVoxelBackend::~BulletVoxelBackend() = default;

void BulletVoxelBackend::bind(const voxel::VoxelData& data) {
  State& s = *m_state;
  if (!data.grid->smooth)
    throw std::runtime_error("backend=\"bullet\" meshes the smooth surface: set surface=\"smooth\"");
  const auto start = std::chrono::steady_clock::now();
  s.clear();
  s.data = data;
  s.surface.build(*data.grid);
  s.blocks.resize(s.surface.blockCount());
  for (size_t b = 0; b < s.surface.blockCount(); ++b) s.attachBlock(b);
  s.world.updateAabbs();
  s.counts.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void BulletVoxelBackend::reserveShell(std::span<const ShellPoint> shell) {
  State& s = *m_state;
  if (s.findShell(shell)) return;
  double radius = 0;
  for (const ShellPoint& p : shell) radius = std::max(radius, p.position.norm());
  for (const ShellPoint& p : shell)
    if (!(p.position.norm() > (1 - 1e-9) * radius))
      throw std::runtime_error(
          "backend=\"bullet\" takes a spherical burr (every shell point at one radius, as PointshellTool); this "
          "tool's shell is not a sphere");
  s.shells.push_back({shell.data(), shell.size(), radius});
}

voxel::VoxelContact BulletVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  State& s = *m_state;
  ++s.queries;
  const QueryAllocations counting{s.queryAllocations, s.queryBytes};
  voxel::VoxelContact result;
  ShellContact& contact = result.contact;
  const State::Shell* reserved = s.findShell(shell);
  if (!reserved || s.blocks.empty()) return result;
  const Vec3 centre = X_WT.position;
  const double r = reserved->radius;
  ClosestContact c = s.closest(centre, r);
  bool in = false;
  if (c.block < 0) {
    // Nothing within r: free, or the centre deeper than r in the bone (then
    // the closest surface is searched farther out).
    if (!s.inside(centre)) return result;
    const double far = s.data.volume->bounds().diagonal().norm();
    for (double reach = 2 * r; c.block < 0 && reach < 2 * far; reach *= 2) c = s.closest(centre, reach);
    if (c.block < 0) return result;
    in = true;
  } else if (c.distance > 0) {
    in = s.behindClosest(centre, c);
  }
  contact = voxel::sphereContact(X_WT, shell, r, c.point, c.distance, in, c.weighted);
  if (contact.points == 0) return result;
  contact.primitives = c.contacts;
  ++s.counts.contactFrames;
  return result;
}

size_t BulletVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  State& s = *m_state;
  const State::Shell* reserved = s.findShell(shell);
  if (!reserved || s.blocks.empty()) return 0;
  BlockTriangles blocks;
  blocks.min = toBullet(X_WT.position - Vec3::Constant(reserved->radius));
  blocks.max = toBullet(X_WT.position + Vec3::Constant(reserved->radius));
  s.broadphase.aabbTest(blocks.min, blocks.max, blocks);
  return blocks.count.triangles;
}

SweepResult BulletVoxelBackend::sweep(const SweepQuery& query) const {
  const State& s = *m_state;
  ++s.queries;
  const QueryAllocations counting{s.queryAllocations, s.queryBytes};
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length) || s.blocks.empty()) return result;
  const State::Shell* reserved = s.findShell(query.shell);
  const double radius = reserved ? reserved->radius : query.leadingRadius;
  // The mesh back-ends' rule (sweepAllowance), cast as a sphere shrunk by the
  // depth it allows.
  const ClosestContact start = s.closest(query.from, radius);
  const bool touching = start.block >= 0 && start.distance < radius;
  // The centre in bone: only new material blocks (as the native sweeps), so
  // the tool may leave; treated as free.
  if (touching ? start.distance > 0 && s.behindClosest(query.from, start) : s.inside(query.from)) return result;
  const double allowed =
      voxel::sweepAllowance(touching, radius - start.distance, voxel::meshSkin(s.data.grid->smallestSide()));
  const double castRadius = radius - allowed;
  if (!(castRadius > kSweepTolerance)) return result;
  btCollisionWorld::ClosestConvexResultCallback hit(toBullet(query.from), toBullet(query.to));
  s.sphere.setUnscaledRadius(castRadius);
  s.world.convexSweepTest(&s.sphere, at(query.from), at(query.to), hit);
  ++s.casts;
  if (!hit.hasHit()) return result;
  result.blocked = true;
  // Back off by the tolerance, so the stop itself is free.
  result.freeFraction = std::max(0.0, double(hit.m_closestHitFraction) - kSweepTolerance / length);
  result.startsInside = touching && result.freeFraction * length <= kSweepTolerance;
  result.contactPoint = fromBullet(hit.m_hitPointWorld);
  return result;
}

bool BulletVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  ++s.queries;
  const QueryAllocations counting{s.queryAllocations, s.queryBytes};
  const State::Shell* reserved = s.findShell(shell);
  if (!reserved || s.blocks.empty()) return false;
  // Visibly in: the sphere pulled one voxel in still reaches the bone, or the
  // centre is in it.
  const double inset = s.data.grid->spacing.maxCoeff();
  if (reserved->radius > inset && s.closest(X_WT.position, reserved->radius - inset).block >= 0) return true;
  return s.inside(X_WT.position);
}

std::optional<SurfaceHit> BulletVoxelBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                      double maxDistance) const {
  const State& s = *m_state;
  if (s.blocks.empty() || !(maxDistance > 0)) return std::nullopt;
  const double far = std::min(maxDistance, 1e7);
  FirstHit hit;
  s.world.rayTest(toBullet(origin), toBullet(origin + far * direction), hit);
  ++s.rays;
  if (!hit.hasHit() || hit.block < 0 || hit.triangle < 0) return std::nullopt;
  SurfaceHit result;
  result.distance = hit.m_closestHitFraction * far;
  result.point = origin + result.distance * direction;
  result.normal = s.faceNormal(hit.block, hit.triangle);
  return result;
}

void BulletVoxelBackend::dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
  State& s = *m_state;
  if (s.blocks.empty()) return;
  const std::vector<size_t> changed = s.surface.update(*s.data.grid, first, last);
  // In the haptic loop: a block Bullet cannot take is counted, not thrown.
  for (const size_t b : changed) {
    try {
      s.attachBlock(b);
    } catch (const std::bad_alloc&) {
      s.blocks[b] = State::Block{};
      ++s.counts.failedBlocks;
    }
  }
  s.counts.rebuiltBlocks += changed.size();
}

void BulletVoxelBackend::reportCounters(std::vector<Counter>& counters) const {
  const State& s = *m_state;
  s.counts.report(counters, s.surface.triangleCount());
  counters.push_back({"contact_tests", double(s.contactTests)});
  counters.push_back({"convex_casts", double(s.casts)});
  counters.push_back({"rays", double(s.rays)});
  counters.push_back({"queries", double(s.queries)});
  counters.push_back({"query_allocations", double(s.queryAllocations)});
  counters.push_back({"query_allocated_bytes", double(s.queryBytes)});
}

}  // namespace trephine::bullet
