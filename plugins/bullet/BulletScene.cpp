#include "plugins/bullet/BulletScene.h"

#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <new>
#include <stdexcept>

#include "framework/core/Component.h"
#include "framework/geometry/ClosestPoint.h"
#include "framework/geometry/MeshSphereContact.h"

namespace trephine::bullet {

namespace {

constexpr double kSweepTolerance = 1e-4;  // mm, as the other back-ends
const Vec3 kParityDirection = Vec3(0.5403, 0.5871, 0.6029).normalized();

// Every allocation Bullet makes goes through btAlignedAlloc: counted here, so
// that the back-ends report what their queries allocate in the haptic loop.
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

// A triangle's share of the contact normal: its face normal (outward) times
// its area (half the cross product), so that the mean does not lean towards
// where the surface happens to be cut into more triangles; the caller
// weights it by depth.
Vec3 areaNormal(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * (b - a).cross(c - a); }

// The closest point of the surface to a sphere's centre: Bullet's trees
// find the triangles whose boxes meet the sphere's box (its dynamic AABB
// tree over the blocks, then each block's BVH), the distance of each is
// computed here, exactly, and those within the radius count. (Bullet's own
// sphere-triangle contacts, through contactTest, report the same triangles
// at several times the cost: a collision algorithm dispatched per triangle.)
struct ClosestInBlock final : btTriangleCallback {
  Vec3 centre = Vec3::Zero();
  double reach = 0;  // mm, the sphere's radius
  int block = -1;
  ClosestTriangle result;
  void processTriangle(btVector3* triangle, int, int index) override {
    const Vec3 v0 = fromBullet(triangle[0]), v1 = fromBullet(triangle[1]), v2 = fromBullet(triangle[2]);
    const Vec3 onMesh = closestOnTriangle(centre, v0, v1, v2);
    const double d = (onMesh - centre).norm();
    if (!(d <= reach)) return;
    ++result.contacts;
    if (d < reach) result.weighted += areaNormal(v0, v1, v2) * (reach - d);
    if (!result.found() || d < result.distance) {
      result.distance = d;
      result.point = onMesh;
      result.which = {block, index};
    }
  }
};
struct ClosestContact final : btBroadphaseAabbCallback {
  ClosestInBlock triangles;
  btVector3 min, max;
  bool process(const btBroadphaseProxy* proxy) override {
    const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    triangles.block = object->getUserIndex();
    static_cast<const btConcaveShape*>(object->getCollisionShape())->processAllTriangles(&triangles, min, max);
    return true;
  }
};
// Counts the surface crossings along a ray (parity: inside when odd). A ray
// through an edge or a vertex hits every triangle there at the same
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
  TriangleRef which;
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result, bool) override {
    if (result.m_hitFraction < m_closestHitFraction) {
      m_closestHitFraction = result.m_hitFraction;
      m_collisionObject = result.m_collisionObject;
      which = {result.m_collisionObject->getUserIndex(),
               result.m_localShapeInfo ? result.m_localShapeInfo->m_triangleIndex : -1};
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

// Bullet's contacts of a convex shape (the shaft) with the surface: the
// deepest (Bullet's depth), and the face normals of the triangles in contact
// weighted by depth (Bullet's own contact normal of a convex shape against a
// triangle leans towards the triangle's edges; the face's does not).
struct ConvexContacts final : btCollisionWorld::ContactResultCallback {
  const btCollisionObject* tool = nullptr;
  const TriangleBlocks* blocks = nullptr;
  double deepest = 0;            // mm
  Vec3 point = Vec3::Zero();     // mm, the deepest contact's point on the surface
  Vec3 normal = Vec3::Zero();    // the deepest contact's face normal
  Vec3 weighted = Vec3::Zero();  // sum of face normal times depth
  int contacts = 0;

  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int, int indexA,
                           const btCollisionObjectWrapper* b, int, int indexB) override {
    const double depth = -double(cp.getDistance());
    if (!(depth > 0)) return 0;  // within Bullet's contact threshold but apart
    const bool toolIsA = a->getCollisionObject() == tool;
    const btCollisionObject* mesh = toolIsA ? b->getCollisionObject() : a->getCollisionObject();
    const Vec3 n = faceNormal(*blocks, {mesh->getUserIndex(), toolIsA ? indexB : indexA});
    ++contacts;
    weighted += depth * n;
    if (depth > deepest) {
      deepest = depth;
      normal = n;
      point = fromBullet(toolIsA ? cp.getPositionWorldOnB() : cp.getPositionWorldOnA());
    }
    return 0;
  }
};

// A sphere cast against one block's triangles, through Bullet's own
// convex cast per triangle (btTriangleConvexcastCallback: GJK against each
// triangle in the swept box), but for the triangles the sphere cannot reach:
// a triangle farther than the cast radius from the path of the centre
// (segmentTriangleDistance) is skipped. Near a contact the swept box holds hundreds of the
// isosurface's small triangles of which a handful come within reach, and
// Bullet's convexSweepTest would cast against every one.
struct CulledSphereCast final : btTriangleConvexcastCallback {
  CulledSphereCast(const btConvexShape* sphere, const btTransform& from, const btTransform& to, double radius)
      : btTriangleConvexcastCallback(sphere, from, to, btTransform::getIdentity(), 0),
        m_from(fromBullet(from.getOrigin())),
        m_to(fromBullet(to.getOrigin())),
        m_radius(radius) {}
  void processTriangle(btVector3* triangle, int partId, int triangleIndex) override {
    const Vec3 a = fromBullet(triangle[0]), b = fromBullet(triangle[1]), c = fromBullet(triangle[2]);
    if (segmentTriangleDistance(m_from, m_to, a, b, c) > m_radius + kSweepTolerance) {
      ++culled;
      return;
    }
    ++cast;
    btTriangleConvexcastCallback::processTriangle(triangle, partId, triangleIndex);
  }
  btScalar reportHit(const btVector3&, const btVector3& hitPoint, btScalar fraction, int, int) override {
    if (fraction < m_hitFraction) {
      m_hitFraction = fraction;  // the later triangles need only beat it
      point = fromBullet(hitPoint);
      hit = true;
    }
    return m_hitFraction;
  }
  bool hit = false;
  Vec3 point = Vec3::Zero();
  uint64_t culled = 0, cast = 0;

 private:
  Vec3 m_from, m_to;
  double m_radius;
};
// Every block whose box meets the sweep's box, cast against.
struct BlockCasts final : btBroadphaseAabbCallback {
  CulledSphereCast* cast = nullptr;
  btVector3 from, to, boxMin, boxMax;  // the path, and the sphere's box around its centre
  bool process(const btBroadphaseProxy* proxy) override {
    const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    const auto* shape = static_cast<const btBvhTriangleMeshShape*>(object->getCollisionShape());
    const_cast<btBvhTriangleMeshShape*>(shape)->performConvexcast(cast, from, to, boxMin, boxMax);
    return true;
  }
};
Box3 boundsOf(const TriangleMesh& mesh) {
  Box3 box;
  for (const Vec3& v : mesh.vertices) box.extend(v);
  return box;
}

}  // namespace

// Installed before the first Bullet object of a back-end is made (malloc and
// free underneath, as Bullet's own default, so earlier blocks free alike).
AllocationHook::AllocationHook() { btAlignedAllocSetCustom(countingAlloc, countingFree); }

BulletShaft::BulletShaft(const ToolSolid& solid)
    : m_burrRadius(solid.radius),
      m_radius(solid.shaftRadius),
      m_length(solid.shaftLength),
      m_axis(solid.shaftAxis.normalized()),
      m_shape(btVector3(solid.shaftRadius, solid.shaftRadius, 0.5 * solid.shaftLength)) {
  // Bullet's cylinder lies along its z axis, centred: turned onto the shaft's
  // axis and moved half its length along it.
  const Quat toAxis = rotationBetween(Vec3::UnitZ(), solid.shaftAxis.normalized());
  m_local = btTransform(btQuaternion(toAxis.x(), toAxis.y(), toAxis.z(), toAxis.w()),
                        toBullet(0.5 * solid.shaftLength * solid.shaftAxis.normalized()));
  // A thousandth of a millimetre of margin (Bullet's default, 0.04, rounds
  // the cylinder's rim by as much and takes 0.01 mm off a tilted shaft's depth).
  m_shape.setMargin(1e-3);
  m_object.setCollisionShape(&m_shape);
}

void BulletTools::describe(std::span<const ShellPoint> shell, const ToolSolid& solid, const std::string& owner) {
  const ReservedShell* reserved = m_shells.find(shell);
  if (!reserved || reserved->sphere) return;
  if (!(solid.shaftLength > 0 && solid.radius > 0 && solid.shaftRadius > 0))
    throw std::runtime_error(owner +
                             " takes a spherical burr (every shell point at one radius, as PointshellTool) or a "
                             "burr on a shaft (CapsuleTool); this tool's shell is not a sphere and it describes no "
                             "shaft");
  for (auto& [source, shaft] : m_shafts)
    if (source == shell.data()) return;
  m_shafts.emplace_back(shell.data(), std::make_unique<BulletShaft>(solid));
}

std::optional<BulletTools::Tool> BulletTools::find(std::span<const ShellPoint> shell) const {
  const ReservedShell* reserved = m_shells.find(shell);
  if (!reserved) return std::nullopt;
  if (reserved->sphere) return Tool{reserved->radius, nullptr};
  for (const auto& [source, shaft] : m_shafts)
    if (source == shell.data()) return Tool{shaft->burrRadius(), shaft.get()};
  return std::nullopt;
}

BulletScene::BulletScene() = default;
BulletScene::~BulletScene() { clear(); }

void BulletScene::clear() {
  for (Block& b : m_blocks)
    if (b.object) m_world.removeCollisionObject(b.object.get());
  m_blocks.clear();
}

void BulletScene::build(const TriangleBlocks& blocks, double deformationMargin) {
  const auto start = std::chrono::steady_clock::now();
  clear();
  m_source = &blocks;
  m_margin = deformationMargin;
  m_bounds.setEmpty();
  m_blocks.resize(blocks.blockCount());
  for (size_t b = 0; b < blocks.blockCount(); ++b) {
    attachBlock(b);
    m_bounds.extend(m_blocks[b].treeBounds);
  }
  m_world.updateAabbs();
  m_counts.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// (Re)builds the Bullet mesh of block `index` from its triangles.
void BulletScene::attachBlock(size_t index) {
  Block& b = m_blocks[index];
  if (b.object) m_world.removeCollisionObject(b.object.get());
  b = Block{};
  const TriangleMesh& mesh = m_source->block(index);
  if (mesh.triangles.empty()) return;
  // Bullet reads the block's own arrays: int triples, and (double
  // precision) btScalar triples with Eigen's layout.
  static_assert(sizeof(Vec3) == 3 * sizeof(btScalar));
  b.mesh = std::make_unique<btTriangleIndexVertexArray>(
      int(mesh.triangles.size()), const_cast<int*>(mesh.triangles.front().data()), int(3 * sizeof(int32_t)),
      int(mesh.vertices.size()), const_cast<btScalar*>(mesh.vertices.front().data()), int(sizeof(Vec3)));
  // The quantized tree covers the vertices' bounds grown by the margin, so
  // that a refit holds them while they move within it.
  const Box3 box = boundsOf(mesh);
  const Vec3 grow = Vec3::Constant(m_margin);
  b.treeBounds = Box3(box.min() - grow, box.max() + grow);
  b.shape = std::make_unique<btBvhTriangleMeshShape>(b.mesh.get(), true, toBullet(b.treeBounds.min()),
                                                     toBullet(b.treeBounds.max()), true);
  // The shape's box is the tree's bounds, so that it holds the vertices
  // wherever they move within them (grows it only; nothing is refitted here).
  if (m_margin > 0) b.shape->partialRefitTree(toBullet(b.treeBounds.min()), toBullet(b.treeBounds.max()));
  b.shape->setMargin(0);  // the triangles themselves, not a shell around them
  b.object = std::make_unique<btCollisionObject>();
  b.object->setCollisionShape(b.shape.get());
  b.object->setUserIndex(int(index));
  m_world.addCollisionObject(b.object.get());
}

void BulletScene::rebuildBlocks(std::span<const size_t> changed) {
  if (m_blocks.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  for (const size_t b : changed) {
    try {
      attachBlock(b);
    } catch (const std::bad_alloc&) {
      m_blocks[b] = Block{};
      ++m_counts.failedBlocks;
    }
  }
  // The broadphase takes the new objects as they are added: one figure for both.
  m_counts.blockBuildMs +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  m_counts.rebuiltBlocks += changed.size();
}

void BulletScene::moveVertices(size_t index, bool rebuild) {
  Block& b = m_blocks[index];
  if (!b.shape) return;
  const QueryAllocations counting{m_followAllocations, m_followBytes};
  if (rebuild) {
    attachBlock(index);  // a fresh tree over the vertices' bounds now, grown by the margin
    m_bounds.extend(b.treeBounds);
    ++m_counts.rebuiltBlocks;
    return;
  }
  // Every node of the tree is refitted; the shape's own box stays the tree's
  // bounds (set at the build), which hold the vertices. Bullet's refitTree
  // would also rescan every triangle six times for a tighter box.
  b.shape->getOptimizedBvh()->refit(b.mesh.get(), toBullet(b.treeBounds.min()), toBullet(b.treeBounds.max()));
  ++m_refits;
}

double BulletScene::farDistance() const { return 2.0 * m_bounds.diagonal().norm() + 10.0; }

ClosestTriangle BulletScene::closest(const Vec3& centre, double radius) const {
  ClosestContact c;
  c.triangles.centre = centre;
  c.triangles.reach = radius;
  c.min = toBullet(centre - Vec3::Constant(radius));
  c.max = toBullet(centre + Vec3::Constant(radius));
  const_cast<btDbvtBroadphase&>(m_broadphase).aabbTest(c.min, c.max, c);
  ++m_contactTests;
  return c.triangles.result;
}

// Whether `centre` is inside, given its closest surface point: behind that
// triangle when the point is inside its face (the direction is along the
// face normal); at an edge or a vertex the faces there disagree, so a ray decides.
bool BulletScene::behindClosest(const Vec3& centre, const ClosestTriangle& c) const {
  const Vec3 n = faceNormal(*m_source, c.which);
  const double along = (centre - c.point).dot(n) / c.distance;
  return std::abs(along) > 0.999 ? along < 0 : inside(centre);
}

bool BulletScene::inside(const Vec3& p) const {
  CrossingCount count;
  m_world.rayTest(toBullet(p), toBullet(p + farDistance() * kParityDirection), count);
  ++m_rays;
  return count.crossings() % 2 == 1;
}

size_t BulletScene::trianglesWithin(const Vec3& p, double radius) const {
  if (m_blocks.empty()) return 0;
  BlockTriangles blocks;
  blocks.min = toBullet(p - Vec3::Constant(radius));
  blocks.max = toBullet(p + Vec3::Constant(radius));
  const_cast<btDbvtBroadphase&>(m_broadphase).aabbTest(blocks.min, blocks.max, blocks);
  return blocks.count.triangles;
}

ShellContact BulletScene::sphereContact(const Pose& X_WT, std::span<const ShellPoint> shell, double radius,
                                        ClosestTriangle* nearest) const {
  ++m_queries;
  const QueryAllocations counting{m_queryAllocations, m_queryBytes};
  if (m_blocks.empty()) return {};
  const Vec3& centre = X_WT.position;
  ClosestTriangle c = closest(centre, radius);
  bool in = false;
  if (!c.found()) {
    // Nothing within r: free, or the centre deeper than r inside (then the
    // closest surface is searched farther out).
    if (!inside(centre)) return {};
    const double far = m_bounds.diagonal().norm();
    for (double reach = 2 * radius; !c.found() && reach < 2 * far; reach *= 2) c = closest(centre, reach);
    if (!c.found()) return {};
    in = true;
  } else if (c.distance > 0) {
    in = behindClosest(centre, c);
  }
  ShellContact contact = trephine::sphereContact(X_WT, shell, radius, c.point, c.distance, in, c.weighted);
  if (contact.points == 0) return {};
  contact.primitives = c.contacts;
  ++m_counts.contactFrames;
  if (nearest) *nearest = c;
  return contact;
}

ShellContact BulletScene::toolContact(const Pose& X_WT, std::span<const ShellPoint> shell, double radius,
                                      const BulletShaft* shaft, ClosestTriangle* nearest) const {
  ShellContact burr = sphereContact(X_WT, shell, radius, nearest);
  if (!shaft || m_blocks.empty()) return burr;
  ++m_queries;
  const QueryAllocations counting{m_queryAllocations, m_queryBytes};
  ConvexContacts c;
  c.tool = &shaft->m_object;
  c.blocks = m_source;
  const btTransform X(
      btQuaternion(X_WT.orientation.x(), X_WT.orientation.y(), X_WT.orientation.z(), X_WT.orientation.w()),
      toBullet(X_WT.position));
  shaft->m_object.setWorldTransform(X * shaft->m_local);
  const_cast<btCollisionWorld&>(m_world).contactTest(&shaft->m_object, c);
  ++m_contactTests;
  if (c.contacts == 0) return burr;
  if (burr.points == 0) ++m_counts.contactFrames;
  ShellContact contact;
  const Vec3 weighted = burr.penetration * burr.normal + c.weighted;
  contact.normal = weighted.norm() > 1e-12 ? Vec3(weighted.normalized()) : c.normal;
  // Bullet's depth of a convex shape against a triangle is how far it must
  // move to leave that triangle, which for a shaft buried deeper than its
  // radius is through the triangle, about the radius, however deep it is. The
  // depth is measured as every back-end measures it: the shaft's deepest
  // point along the contact normal (its support point, on the rim of one of
  // its ends), from there along the normal to the surface.
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  const Vec3 axis = R * shaft->m_axis;
  const Vec3 down = -contact.normal;
  const Vec3 across = down - down.dot(axis) * axis;
  const Vec3 rim = across.norm() > 1e-9 ? Vec3(shaft->m_radius * across.normalized()) : Vec3::Zero();
  const Vec3 lowest = X_WT.position + (axis.dot(down) > 0 ? Vec3(shaft->m_length * axis) : Vec3::Zero()) + rim;
  double deepest = c.deepest;
  if (inside(lowest))
    if (const auto hit = raycast(lowest, contact.normal, farDistance())) deepest = std::max(deepest, hit->distance);
  contact.penetration = std::max(burr.penetration, deepest);
  contact.primitives = burr.primitives + c.contacts;
  // The shaft's shell points beyond the plane of its deepest contact.
  int shaftPoints = 0;
  for (const ShellPoint& p : shell) {
    if (p.position.norm() <= (1 + 1e-9) * radius) continue;  // the burr's
    shaftPoints += (R * p.position + X_WT.position - c.point).dot(c.normal) < 0;
  }
  contact.points = burr.points + std::max(shaftPoints, 1);
  return contact;
}

SweepResult BulletScene::sweepSphere(const SweepQuery& query, double radius, double skin) const {
  ++m_queries;
  const QueryAllocations counting{m_queryAllocations, m_queryBytes};
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length) || m_blocks.empty()) return result;
  // The mesh back-ends' rule (sweepAllowance), cast as a sphere shrunk by the
  // depth it allows.
  const ClosestTriangle start = closest(query.from, radius);
  const bool touching = start.found() && start.distance < radius;
  // The centre inside: only new material blocks (as the native sweeps), so
  // the tool may leave; treated as free.
  if (touching ? start.distance > 0 && behindClosest(query.from, start) : inside(query.from)) return result;
  const double allowed = sweepAllowance(touching, radius - start.distance, skin);
  const double castRadius = radius - allowed;
  if (!(castRadius > kSweepTolerance)) return result;
  m_sphere.setUnscaledRadius(castRadius);
  CulledSphereCast cast(&m_sphere, at(query.from), at(query.to), castRadius);
  BlockCasts blocks;
  blocks.cast = &cast;
  blocks.from = toBullet(query.from);
  blocks.to = toBullet(query.to);
  blocks.boxMin = btVector3(-castRadius, -castRadius, -castRadius);
  blocks.boxMax = btVector3(castRadius, castRadius, castRadius);
  const Vec3 reach = Vec3::Constant(castRadius);
  const_cast<btDbvtBroadphase&>(m_broadphase)
      .aabbTest(toBullet(query.from.cwiseMin(query.to) - reach), toBullet(query.from.cwiseMax(query.to) + reach),
                blocks);
  ++m_casts;
  m_culledTriangles += cast.culled;
  m_castTriangles += cast.cast;
  if (!cast.hit) return result;
  result.blocked = true;
  // Back off by the tolerance, so the stop itself is free.
  result.freeFraction = std::max(0.0, double(cast.m_hitFraction) - kSweepTolerance / length);
  result.startsInside = touching && result.freeFraction * length <= kSweepTolerance;
  result.contactPoint = cast.point;
  return result;
}

bool BulletScene::overlapsSphere(const Vec3& centre, double radius, double inset) const {
  ++m_queries;
  const QueryAllocations counting{m_queryAllocations, m_queryBytes};
  if (m_blocks.empty()) return false;
  if (radius > inset && closest(centre, radius - inset).found()) return true;
  return inside(centre);
}

std::optional<SurfaceHit> BulletScene::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  if (m_blocks.empty() || !(maxDistance > 0)) return std::nullopt;
  const double far = std::min(maxDistance, 1e7);
  FirstHit hit;
  m_world.rayTest(toBullet(origin), toBullet(origin + far * direction), hit);
  ++m_rays;
  if (!hit.hasHit() || !hit.which.valid()) return std::nullopt;
  SurfaceHit result;
  result.distance = hit.m_closestHitFraction * far;
  result.point = origin + result.distance * direction;
  result.normal = faceNormal(*m_source, hit.which);
  return result;
}

void BulletScene::reportCounters(std::vector<Counter>& counters) const {
  m_counts.report(counters, m_source ? m_source->triangleCount() : 0);
  counters.push_back({"contact_tests", double(m_contactTests)});
  counters.push_back({"convex_casts", double(m_casts)});
  // Of the triangles in the sweeps' boxes: cast against, and skipped as out of reach.
  counters.push_back({"cast_triangles", double(m_castTriangles)});
  counters.push_back({"culled_triangles", double(m_culledTriangles)});
  counters.push_back({"rays", double(m_rays)});
  counters.push_back({"queries", double(m_queries)});
  counters.push_back({"query_allocations", double(m_queryAllocations)});
  counters.push_back({"query_allocated_bytes", double(m_queryBytes)});
  if (m_refits || m_counts.rebuiltBlocks) {
    counters.push_back({"refits", double(m_refits)});
    // What following a deforming surface allocates: nothing to refit, a new tree to rebuild.
    counters.push_back({"follow_allocations", double(m_followAllocations)});
    counters.push_back({"follow_allocated_bytes", double(m_followBytes)});
  }
}

}  // namespace trephine::bullet
