#include "plugins/embree/EmbreeScene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "framework/core/Component.h"
#include "framework/geometry/ClosestPoint.h"
#include "framework/geometry/MeshSphereContact.h"

namespace trephine::embree {

namespace {

// Crossings are counted along this direction (unit, away from the axes and
// the cells' diagonals, so a ray rarely grazes a triangle's edge).
const Vec3 kParityDirection = Vec3(0.5403, 0.5871, 0.6029).normalized();
// A ray continues this far past each crossing (mm): triangles closer than
// this along the ray would be counted once.
constexpr double kParityStep = 1e-5;
// Sweeps stop within this of the surface (mm).
constexpr double kSweepTolerance = 1e-4;

struct ClosestQuery {
  const TriangleBlocks* blocks = nullptr;
  Vec3 point = Vec3::Zero();
  double best2 = std::numeric_limits<double>::infinity();
  Vec3 closest = Vec3::Zero();
  TriangleRef which;
  // Averaging: every triangle within `reach` adds its face normal, weighted
  // by how deep the sphere of radius `reach` is in it and by its area (the
  // query radius then stays at `reach`).
  bool average = false;
  double reach = 0;
  Vec3 weighted = Vec3::Zero();
};

bool closestCallback(RTCPointQueryFunctionArguments* args) {
  auto* q = static_cast<ClosestQuery*>(args->userPtr);
  // Each block is its own scene, instanced in the top scene under the block's index.
  const unsigned block = args->context->instID[0];
  const TriangleMesh& mesh = q->blocks->block(block);
  const auto& t = mesh.triangles[args->primID];
  const Vec3 &a = mesh.vertices[size_t(t[0])], &b = mesh.vertices[size_t(t[1])], &v = mesh.vertices[size_t(t[2])];
  const Vec3 c = closestOnTriangle(q->point, a, b, v);
  const double d2 = (c - q->point).squaredNorm();
  if (q->average && d2 < q->reach * q->reach && d2 > 0) {
    // The triangle's share: its face normal (outward) times depth and area
    // (half the cross product), so that the mean does not lean towards where
    // the surface happens to be cut into more triangles.
    q->weighted += 0.5 * (q->reach - std::sqrt(d2)) * (b - a).cross(v - a);
  }
  if (!(d2 < q->best2)) return false;
  q->best2 = d2;
  q->closest = c;
  q->which = {int(block), int(args->primID)};
  if (q->average) return false;  // every triangle within reach is visited
  // Shrink the search to the best distance so far (float, rounded up).
  args->query->radius = std::nextafter(float(std::sqrt(d2)), std::numeric_limits<float>::infinity());
  return true;
}

// The broad phase alone: counts the triangles whose boxes the query reaches.
bool countCallback(RTCPointQueryFunctionArguments* args) {
  ++*static_cast<size_t*>(args->userPtr);
  return false;
}

// Visits the triangles whose boxes come within `radius` of p (rounded up to
// float) with `callback`, which may shrink the query's radius.
void pointQuery(RTCScene scene, const Vec3& p, double radius, RTCPointQueryFunction callback, void* user) {
  RTCPointQuery query;
  query.x = float(p.x()), query.y = float(p.y()), query.z = float(p.z());
  query.time = 0;
  query.radius = std::nextafter(float(radius), std::numeric_limits<float>::infinity());
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene, &query, &context, callback, user);
}

}  // namespace

EmbreeScene::~EmbreeScene() {
  release();
  if (m_device) rtcReleaseDevice(m_device);
}

void EmbreeScene::release() {
  for (size_t b = 0; b < m_blockScenes.size(); ++b) detachBlock(b);
  m_blockScenes.clear();
  if (m_scene) rtcReleaseScene(m_scene), m_scene = nullptr;
}

void EmbreeScene::build(const TriangleBlocks& blocks, bool deforming) {
  const auto start = std::chrono::steady_clock::now();
  if (!m_device) {
    m_device = rtcNewDevice(nullptr);
    if (!m_device)
      throw std::runtime_error("Embree could not create a device (error " +
                               std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  }
  release();
  m_blocks = &blocks;
  m_deforming = deforming;
  m_scene = rtcNewScene(m_device);
  rtcSetSceneFlags(m_scene, RTC_SCENE_FLAG_DYNAMIC);  // its instances change as the surface is cut or moves
  rtcSetSceneBuildQuality(m_scene, RTC_BUILD_QUALITY_LOW);
  m_blockScenes.assign(blocks.blockCount(), Block{});
  for (size_t b = 0; b < blocks.blockCount(); ++b)
    if (!attachBlock(b)) throw std::runtime_error("Embree could not allocate the buffers of a block of the surface");
  rtcCommitScene(m_scene);
  if (rtcGetDeviceError(m_device) != RTC_ERROR_NONE) throw std::runtime_error("Embree failed to build the scene");
  m_counts.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void EmbreeScene::detachBlock(size_t index) {
  Block& b = m_blockScenes[index];
  if (!b.scene) return;
  rtcDetachGeometry(m_scene, unsigned(index));
  if (b.instance) rtcReleaseGeometry(b.instance);
  if (b.triangles) rtcReleaseGeometry(b.triangles);
  rtcReleaseScene(b.scene);
  b = Block{};
}

void EmbreeScene::copyVertices(size_t index) {
  const TriangleMesh& mesh = m_blocks->block(index);
  float* out = m_blockScenes[index].vertices;
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) out[3 * v + size_t(a)] = float(mesh.vertices[v][a]);
}

// (Re)builds block `index`'s scene from its triangles and puts its instance
// in the top scene (committed by the caller). Only this block's BVH is
// built: a drilled frame rebuilds the blocks it changed and the top level
// over the instances, not the whole surface. False when Embree could not
// allocate the block's buffers (the block is then left out).
bool EmbreeScene::attachBlock(size_t index) {
  detachBlock(index);
  const TriangleMesh& mesh = m_blocks->block(index);
  if (mesh.triangles.empty()) return true;
  Block& b = m_blockScenes[index];
  RTCGeometry geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
  // A deforming block is refitted: the block scene is two-level (LOW) so the
  // geometry's own build quality (REFIT) is used.
  if (m_deforming) rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_REFIT);
  b.vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(unsigned), mesh.triangles.size()));
  if (!b.vertices || !indices) {
    rtcReleaseGeometry(geometry);
    b = Block{};
    return false;
  }
  copyVertices(index);
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int a = 0; a < 3; ++a) indices[3 * t + size_t(a)] = unsigned(mesh.triangles[t][size_t(a)]);
  rtcCommitGeometry(geometry);
  b.scene = rtcNewScene(m_device);
  if (m_deforming) {
    rtcSetSceneFlags(b.scene, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(b.scene, RTC_BUILD_QUALITY_LOW);
  }
  rtcAttachGeometry(b.scene, geometry);
  rtcCommitScene(b.scene);
  if (m_deforming) {
    b.triangles = geometry;
  } else {
    rtcReleaseGeometry(geometry);  // the scene keeps it
  }
  RTCGeometry instance = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(instance, b.scene);
  const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};  // 3x4, column major
  rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
  rtcCommitGeometry(instance);
  rtcAttachGeometryByID(m_scene, instance, unsigned(index));
  b.instance = instance;
  return true;
}

void EmbreeScene::rebuildBlocks(std::span<const size_t> changed) {
  if (!m_scene) return;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  for (const size_t b : changed) m_counts.failedBlocks += attachBlock(b) ? 0 : 1;
  const auto built = Clock::now();
  if (!changed.empty()) rtcCommitScene(m_scene);
  m_counts.blockBuildMs += std::chrono::duration<double, std::milli>(built - start).count();
  m_counts.topBuildMs += std::chrono::duration<double, std::milli>(Clock::now() - built).count();
  m_counts.rebuiltBlocks += changed.size();
}

void EmbreeScene::moveVertices(size_t index, bool rebuild) {
  Block& b = m_blockScenes[index];
  if (!m_scene || !b.scene || !b.triangles) return;
  copyVertices(index);
  rtcUpdateGeometryBuffer(b.triangles, RTC_BUFFER_TYPE_VERTEX, 0);
  if (rebuild) rtcSetGeometryBuildQuality(b.triangles, RTC_BUILD_QUALITY_MEDIUM);
  rtcCommitGeometry(b.triangles);
  rtcCommitScene(b.scene);
  if (rebuild) {
    rtcSetGeometryBuildQuality(b.triangles, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(b.triangles);
    ++m_counts.rebuiltBlocks;
  } else {
    ++m_refits;
  }
  rtcCommitGeometry(b.instance);  // the instance's bounds follow its scene's
  rtcCommitScene(m_scene);
}

bool EmbreeScene::closest(const Vec3& p, double radius, Vec3& point, double& distance, Vec3* averaged,
                          TriangleRef* which) const {
  ClosestQuery q;
  q.blocks = m_blocks;
  q.point = p;
  q.best2 = radius * radius;
  q.average = averaged != nullptr;
  q.reach = radius;
  pointQuery(m_scene, p, radius, closestCallback, &q);
  ++m_pointQueries;
  if (!q.which.valid()) return false;
  point = q.closest;
  distance = std::sqrt(q.best2);
  if (averaged) *averaged = q.weighted;
  if (which) *which = q.which;
  return true;
}

double EmbreeScene::firstHit(const Vec3& origin, const Vec3& direction, double near, double far,
                             TriangleRef& hit) const {
  RTCRayHit rh;
  rh.ray.org_x = float(origin.x()), rh.ray.org_y = float(origin.y()), rh.ray.org_z = float(origin.z());
  rh.ray.dir_x = float(direction.x()), rh.ray.dir_y = float(direction.y()), rh.ray.dir_z = float(direction.z());
  rh.ray.tnear = float(near);
  rh.ray.tfar = float(far);
  rh.ray.time = 0;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(m_scene, &context, &rh);
  ++m_rays;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return -1;
  hit = {int(rh.hit.instID[0]), int(rh.hit.primID)};  // the block, the triangle
  return rh.ray.tfar;
}

bool EmbreeScene::inside(const Vec3& p) const {
  int crossings = 0;
  double near = 0;
  TriangleRef hit;
  for (int n = 0; n < 256; ++n) {
    const double t = firstHit(p, kParityDirection, near, std::numeric_limits<float>::infinity(), hit);
    if (t < 0) break;
    ++crossings;
    near = t + kParityStep;
  }
  return crossings % 2 == 1;
}

size_t EmbreeScene::trianglesWithin(const Vec3& p, double radius) const {
  size_t candidates = 0;
  pointQuery(m_scene, p, radius, countCallback, &candidates);
  return candidates;
}

ShellContact EmbreeScene::sphereContact(const Pose& X_WT, std::span<const ShellPoint> shell, double radius,
                                        TriangleRef* closestTriangle, Vec3* closestPoint) const {
  const Vec3& centre = X_WT.position;
  Vec3 point = Vec3::Zero(), averaged = Vec3::Zero();
  double d = 0;
  TriangleRef which;
  const bool near = closest(centre, radius, point, d, &averaged, &which);
  const bool in = inside(centre);
  if (!near && !in) return {};
  if (in && !near && !closest(centre, std::numeric_limits<float>::max(), point, d, nullptr, &which)) return {};
  ShellContact contact = trephine::sphereContact(X_WT, shell, radius, point, d, in, averaged);
  if (contact.points == 0) return {};
  contact.primitives = 1;
  ++m_counts.contactFrames;
  if (closestTriangle) *closestTriangle = which;
  if (closestPoint) *closestPoint = point;
  return contact;
}

SweepResult EmbreeScene::sweepSphere(const SweepQuery& query, double radius, const SphereQueryScale& scale) const {
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length) || !m_scene) return result;
  // The centre inside: only new material blocks (as the native sweeps), so
  // the tool may leave; treated as free.
  if (inside(query.from)) return result;
  Vec3 closestPoint = Vec3::Zero();
  double d = 0;
  const bool touching = closest(query.from, radius, closestPoint, d);
  const double allowed = sweepAllowance(touching, radius - d, scale.skin);
  // Depth of the sphere at fraction t of the path, and where it touches.
  const auto depthAt = [&](double t, Vec3& touch) {
    double distance = 0;
    return closest(query.from + t * path, radius, touch, distance) ? radius - distance : -1.0;
  };
  // Samples `sweepStep` apart, each exact; the first too deep is refined by bisection.
  const int steps = std::max(1, int(std::ceil(length / scale.sweepStep)));
  double before = 0;
  for (int k = 1; k <= steps; ++k) {
    const double t = double(k) / steps;
    Vec3 touch = Vec3::Zero();
    if (!(depthAt(t, touch) > allowed + kSweepTolerance)) {
      before = t;
      continue;
    }
    double lo = before, hi = t;
    for (int n = 0; n < 40 && (hi - lo) * length > kSweepTolerance; ++n) {
      const double mid = 0.5 * (lo + hi);
      Vec3 at = Vec3::Zero();
      (depthAt(mid, at) > allowed ? hi : lo) = mid;
      if (depthAt(hi, at) > allowed) touch = at;
    }
    result.blocked = true;
    result.freeFraction = lo;
    result.startsInside = touching && lo * length <= kSweepTolerance;
    result.contactPoint = touch;
    return result;
  }
  return result;
}

bool EmbreeScene::overlapsSphere(const Vec3& centre, double radius, const SphereQueryScale& scale) const {
  if (!m_scene) return false;
  if (inside(centre)) return true;
  Vec3 point = Vec3::Zero();
  double d = 0;
  return radius > scale.inset && closest(centre, radius - scale.inset, point, d);
}

std::optional<SurfaceHit> EmbreeScene::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  if (!m_scene) return std::nullopt;
  TriangleRef which;
  const double t = firstHit(origin, direction, 0, maxDistance, which);
  if (t < 0) return std::nullopt;
  SurfaceHit hit;
  hit.distance = t;
  hit.point = origin + t * direction;
  hit.normal = faceNormal(*m_blocks, which);
  return hit;
}

void EmbreeScene::reportCounters(std::vector<Counter>& counters) const {
  m_counts.report(counters, m_blocks ? m_blocks->triangleCount() : 0);
  counters.push_back({"rays", double(m_rays)});
  counters.push_back({"point_queries", double(m_pointQueries)});
  if (m_deforming) counters.push_back({"refits", double(m_refits)});
}

}  // namespace trephine::embree
