#include "plugins/embree/EmbreeVoxelBackend.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "framework/core/Component.h"
#include "framework/geometry/ClosestPoint.h"
#include "plugins/voxel_skull/IsoSurface.h"
#include "plugins/voxel_skull/MeshSphereContact.h"
#include "plugins/voxel_skull/MeshSurfaceCounters.h"

namespace trephine::embree {

namespace {

// Crossings are counted along this direction (unit, away from the axes and
// the cells' diagonals, so a ray rarely grazes a triangle's edge).
const Vec3 kParityDirection = Vec3(0.5403, 0.5871, 0.6029).normalized();
// A ray continues this far past each crossing (mm): triangles closer than
// this along the ray would be counted once.
constexpr double kParityStep = 1e-5;
// Conservative advancement stops within this of the surface (mm).
constexpr double kSweepTolerance = 1e-4;

struct ClosestQuery {
  const voxel::BlockedIsoSurface* surface = nullptr;
  Vec3 point = Vec3::Zero();
  double best2 = std::numeric_limits<double>::infinity();
  Vec3 closest = Vec3::Zero();
  bool found = false;
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
  const voxel::TriangleMesh& mesh = q->surface->block(args->context->instID[0]);
  const auto& t = mesh.triangles[args->primID];
  const Vec3 c = closestOnTriangle(q->point, mesh.vertices[size_t(t[0])], mesh.vertices[size_t(t[1])],
                                   mesh.vertices[size_t(t[2])]);
  const double d2 = (c - q->point).squaredNorm();
  if (q->average && d2 < q->reach * q->reach && d2 > 0) {
    // The triangle's share: its face normal (out of the bone) times depth and
    // area (half the cross product), so that the mean does not lean towards
    // where the surface happens to be cut into more triangles.
    const Vec3 &a = mesh.vertices[size_t(t[0])], &b = mesh.vertices[size_t(t[1])], &v = mesh.vertices[size_t(t[2])];
    q->weighted += 0.5 * (q->reach - std::sqrt(d2)) * (b - a).cross(v - a);
  }
  if (!(d2 < q->best2)) return false;
  q->best2 = d2;
  q->closest = c;
  q->found = true;
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

}  // namespace

struct EmbreeVoxelBackend::State {
  voxel::VoxelData data;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;  // the top scene: one instance per block with triangles, its ID the block's index
  voxel::BlockedIsoSurface surface;
  std::vector<RTCScene> blockScenes;  // per block: its triangles, or null when it has none
  struct Shell {
    const ShellPoint* source = nullptr;
    size_t size = 0;
    double radius = 0;    // mm, the farthest point from the reference point
    bool sphere = false;  // every point at `radius`
  };
  std::vector<Shell> shells;
  mutable std::vector<double> depths;  // per shell point, the point-by-point contact
  mutable std::vector<Vec3> normals;
  voxel::MeshSurfaceCounters counts;
  mutable uint64_t rays = 0, pointQueries = 0;

  ~State() {
    release();
    if (device) rtcReleaseDevice(device);
  }

  void release() {
    for (RTCScene& b : blockScenes)
      if (b) rtcReleaseScene(b), b = nullptr;
    if (scene) rtcReleaseScene(scene), scene = nullptr;
  }

  const Shell* findShell(std::span<const ShellPoint> shell) const {
    for (const Shell& s : shells)
      if (s.source == shell.data() && s.size == shell.size()) return &s;
    return nullptr;
  }

  // (Re)builds block `index`'s scene from its triangles and puts its
  // instance in the top scene (the top scene is committed by the caller).
  // Only this block's BVH is built: a drilled frame rebuilds the blocks it
  // changed and the top level over the instances, not the whole surface.
  // False when Embree could not allocate the block's buffers (the block is
  // then left out).
  bool attachBlock(size_t index) {
    if (blockScenes[index]) {
      rtcDetachGeometry(scene, unsigned(index));
      rtcReleaseScene(blockScenes[index]);
      blockScenes[index] = nullptr;
    }
    const voxel::TriangleMesh& mesh = surface.block(index);
    if (mesh.triangles.empty()) return true;
    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.vertices.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.triangles.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      return false;
    }
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
      for (int a = 0; a < 3; ++a) vertices[3 * v + size_t(a)] = float(mesh.vertices[v][a]);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int a = 0; a < 3; ++a) indices[3 * t + size_t(a)] = unsigned(mesh.triangles[t][size_t(a)]);
    rtcCommitGeometry(geometry);
    RTCScene block = rtcNewScene(device);
    rtcAttachGeometry(block, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(block);
    RTCGeometry instance = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(instance, block);
    const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};  // 3x4, column major
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
    rtcCommitGeometry(instance);
    rtcAttachGeometryByID(scene, instance, unsigned(index));
    rtcReleaseGeometry(instance);
    blockScenes[index] = block;
    return true;
  }

  // The surface point closest to p within `radius` (mm), if any.
  // The closest surface point within `radius` of p; with `averaged`, also the
  // sum of the face normals of the triangles within `radius`, weighted by depth and area.
  bool closest(const Vec3& p, double radius, Vec3& point, double& distance, Vec3* averaged = nullptr) const {
    ClosestQuery q;
    q.surface = &surface;
    q.point = p;
    q.best2 = radius * radius;
    q.average = averaged != nullptr;
    q.reach = radius;
    RTCPointQuery query;
    query.x = float(p.x()), query.y = float(p.y()), query.z = float(p.z());
    query.time = 0;
    query.radius = std::nextafter(float(radius), std::numeric_limits<float>::infinity());
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene, &query, &context, closestCallback, &q);
    ++pointQueries;
    if (!q.found) return false;
    point = q.closest;
    distance = std::sqrt(q.best2);
    if (averaged) *averaged = q.weighted;
    return true;
  }

  // The first crossing of the ray from `origin` along unit `direction` after
  // `near` and before `far` (mm): its distance, or a negative value.
  double firstHit(const Vec3& origin, const Vec3& direction, double near, double far, unsigned& geomID,
                  unsigned& primID) const {
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
    rtcIntersect1(scene, &context, &rh);
    ++rays;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return -1;
    geomID = rh.hit.instID[0];  // the block
    primID = rh.hit.primID;
    return rh.ray.tfar;
  }

  // Inside the bone: an odd number of crossings along kParityDirection.
  bool inside(const Vec3& p) const {
    int crossings = 0;
    double near = 0;
    unsigned geomID = 0, primID = 0;
    for (int n = 0; n < 256; ++n) {
      const double t = firstHit(p, kParityDirection, near, std::numeric_limits<float>::infinity(), geomID, primID);
      if (t < 0) break;
      ++crossings;
      near = t + kParityStep;
    }
    return crossings % 2 == 1;
  }

  Vec3 triangleNormal(unsigned geomID, unsigned primID) const {
    const voxel::TriangleMesh& mesh = surface.block(geomID);
    const auto& t = mesh.triangles[primID];
    const Vec3& a = mesh.vertices[size_t(t[0])];
    return (mesh.vertices[size_t(t[1])] - a).cross(mesh.vertices[size_t(t[2])] - a).normalized();
  }
};

EmbreeVoxelBackend::EmbreeVoxelBackend() : m_state(std::make_unique<State>()) {}
EmbreeVoxelBackend::~EmbreeVoxelBackend() = default;

void EmbreeVoxelBackend::bind(const voxel::VoxelData& data) {
  State& s = *m_state;
  if (!data.grid->smooth)
    throw std::runtime_error("backend=\"embree\" meshes the smooth surface: set surface=\"smooth\"");
  const auto start = std::chrono::steady_clock::now();
  s.data = data;
  if (!s.device) {
    s.device = rtcNewDevice(nullptr);
    if (!s.device)
      throw std::runtime_error("Embree could not create a device (error " +
                               std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  }
  s.release();
  s.scene = rtcNewScene(s.device);
  rtcSetSceneFlags(s.scene, RTC_SCENE_FLAG_DYNAMIC);  // its instances change as the skull is drilled
  rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_LOW);
  s.surface.build(*data.grid);
  s.blockScenes.assign(s.surface.blockCount(), nullptr);
  for (size_t b = 0; b < s.surface.blockCount(); ++b)
    if (!s.attachBlock(b)) throw std::runtime_error("Embree could not allocate the buffers of a block of the surface");
  rtcCommitScene(s.scene);
  if (rtcGetDeviceError(s.device) != RTC_ERROR_NONE) throw std::runtime_error("Embree failed to build the scene");
  s.counts.buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void EmbreeVoxelBackend::reserveShell(std::span<const ShellPoint> shell) {
  State& s = *m_state;
  if (s.findShell(shell)) return;
  State::Shell reserved{shell.data(), shell.size(), 0, true};
  for (const ShellPoint& p : shell) reserved.radius = std::max(reserved.radius, p.position.norm());
  for (const ShellPoint& p : shell)
    reserved.sphere = reserved.sphere && p.position.norm() > (1 - 1e-9) * reserved.radius;
  s.shells.push_back(reserved);
  s.depths.resize(std::max(s.depths.size(), shell.size()));
  s.normals.resize(std::max(s.normals.size(), shell.size()));
}

voxel::VoxelContact EmbreeVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  State& s = *m_state;
  voxel::VoxelContact result;
  ShellContact& contact = result.contact;
  const State::Shell* reserved = s.findShell(shell);
  if (!reserved || !s.scene) return result;
  const Vec3 centre = X_WT.position;
  const double r = reserved->radius;
  if (reserved->sphere) {
    Vec3 closest = Vec3::Zero(), averaged = Vec3::Zero();
    double d = 0;
    const bool near = s.closest(centre, r, closest, d, &averaged);
    const bool in = s.inside(centre);
    if (!near && !in) return result;
    if (in && !near && !s.closest(centre, std::numeric_limits<float>::max(), closest, d)) return result;
    contact = voxel::sphereContact(X_WT, shell, r, closest, d, in, averaged);
    if (contact.points == 0) return result;
    contact.primitives = 1;
    ++s.counts.contactFrames;
    return result;
  }
  // Any other shell, point by point.
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  Vec3 weighted = Vec3::Zero();
  for (size_t i = 0; i < shell.size(); ++i) {
    s.depths[i] = 0;
    const Vec3 p = R * shell[i].position + centre;
    if (!s.inside(p)) continue;
    Vec3 closest = Vec3::Zero();
    double d = 0;
    if (!s.closest(p, 2 * r, closest, d) || !(d > 0)) continue;
    s.depths[i] = d;
    s.normals[i] = (closest - p) / d;
    weighted += d * s.normals[i];
    ++contact.points;
  }
  if (contact.points == 0) return result;
  contact.normal = weighted.norm() > 1e-12 ? Vec3(weighted.normalized()) : Vec3::Zero();
  for (size_t i = 0; i < shell.size(); ++i)
    if (s.depths[i] > 0)
      contact.penetration =
          std::max(contact.penetration, s.depths[i] * std::max(0.0, s.normals[i].dot(contact.normal)));
  contact.primitives = contact.points;
  ++s.counts.contactFrames;
  return result;
}

size_t EmbreeVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const State& s = *m_state;
  const State::Shell* reserved = s.findShell(shell);
  if (!reserved || !s.scene) return 0;
  size_t candidates = 0;
  RTCPointQuery query;
  query.x = float(X_WT.position.x()), query.y = float(X_WT.position.y()), query.z = float(X_WT.position.z());
  query.time = 0;
  query.radius = std::nextafter(float(reserved->radius), std::numeric_limits<float>::infinity());
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(s.scene, &query, &context, countCallback, &candidates);
  return candidates;
}

SweepResult EmbreeVoxelBackend::sweep(const SweepQuery& query) const {
  const State& s = *m_state;
  SweepResult result;
  const Vec3 path = query.to - query.from;
  const double length = path.norm();
  if (!(length > 0) || !std::isfinite(length) || !s.scene) return result;
  const State::Shell* reserved = s.findShell(query.shell);
  const double radius = reserved ? reserved->radius : query.leadingRadius;
  // The centre in bone: only new material blocks (as the native sweeps), so
  // the tool may leave; treated as free.
  if (s.inside(query.from)) return result;
  Vec3 closest = Vec3::Zero();
  double d = 0;
  const bool touching = s.closest(query.from, radius, closest, d);
  const double allowed = voxel::sweepAllowance(touching, radius - d, voxel::meshSkin(s.data.grid->smallestSide()));
  // Depth of the sphere at fraction t of the path, and where it touches.
  const auto depthAt = [&](double t, Vec3& touch) {
    double distance = 0;
    return s.closest(query.from + t * path, radius, touch, distance) ? radius - distance : -1.0;
  };
  // Samples half a voxel apart, each exact; the first too deep is refined by bisection.
  const int steps = std::max(1, int(std::ceil(length / (0.5 * s.data.grid->smallestSide()))));
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

bool EmbreeVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const State::Shell* reserved = s.findShell(shell);
  if (!reserved || !s.scene) return false;
  if (s.inside(X_WT.position)) return true;
  // Visibly in: the shell pulled one voxel in reaches the bone.
  const double inset = s.data.grid->spacing.maxCoeff();
  Vec3 closest = Vec3::Zero();
  double d = 0;
  return reserved->radius > inset && s.closest(X_WT.position, reserved->radius - inset, closest, d);
}

std::optional<SurfaceHit> EmbreeVoxelBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                      double maxDistance) const {
  const State& s = *m_state;
  if (!s.scene) return std::nullopt;
  unsigned geomID = 0, primID = 0;
  const double t = s.firstHit(origin, direction, 0, maxDistance, geomID, primID);
  if (t < 0) return std::nullopt;
  SurfaceHit hit;
  hit.distance = t;
  hit.point = origin + t * direction;
  hit.normal = s.triangleNormal(geomID, primID);
  return hit;
}

void EmbreeVoxelBackend::dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
  State& s = *m_state;
  if (!s.scene) return;
  const std::vector<size_t> changed = s.surface.update(*s.data.grid, first, last);
  // In the haptic loop: a block Embree cannot take is counted, not thrown.
  for (const size_t b : changed) s.counts.failedBlocks += s.attachBlock(b) ? 0 : 1;
  if (!changed.empty()) rtcCommitScene(s.scene);
  s.counts.rebuiltBlocks += changed.size();
}

void EmbreeVoxelBackend::reportCounters(std::vector<Counter>& counters) const {
  const State& s = *m_state;
  s.counts.report(counters, s.surface.triangleCount());
  counters.push_back({"rays", double(s.rays)});
  counters.push_back({"point_queries", double(s.pointQueries)});
}

}  // namespace trephine::embree
