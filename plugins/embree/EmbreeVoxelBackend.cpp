#include "plugins/embree/EmbreeVoxelBackend.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "framework/geometry/MeshSphereContact.h"
#include "plugins/embree/EmbreeScene.h"
#include "framework/data/IsoSurface.h"

namespace trephine::embree {

struct EmbreeVoxelBackend::State {
  voxel::VoxelData data;
  BlockedIsoSurface surface;
  EmbreeScene scene;
  ReservedShells shells;
  mutable std::vector<double> depths;  // per shell point, the point-by-point contact
  mutable std::vector<Vec3> normals;
  // The proxy rests a tenth of the smallest voxel side deep; sweeps sample
  // every half voxel; a displayed burr one voxel in overlaps.
  SphereQueryScale scale() const {
    const double side = data.grid->smallestSide();
    return {0.1 * side, 0.5 * side, data.grid->spacing.maxCoeff()};
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
  s.surface.build(*data.grid, data.grid->cellsWithoutSurface());
  s.scene.build(s.surface, false);
  // The build time counts the extraction too.
  s.scene.counts().buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void EmbreeVoxelBackend::reserveShell(std::span<const ShellPoint> shell) {
  State& s = *m_state;
  s.shells.add(shell);
  s.depths.resize(std::max(s.depths.size(), shell.size()));
  s.normals.resize(std::max(s.normals.size(), shell.size()));
}

voxel::VoxelContact EmbreeVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  State& s = *m_state;
  voxel::VoxelContact result;
  const ReservedShell* reserved = s.shells.find(shell);
  if (!reserved || s.scene.empty()) return result;
  if (reserved->sphere) {
    result.contact = s.scene.sphereContact(X_WT, shell, reserved->radius);
    return result;
  }
  // Any other shell, point by point: inside by ray parity, depth to the
  // closest point, normals weighted by depth, the deepest along the contact
  // normal (as the native deepest-point variant).
  ShellContact& contact = result.contact;
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  Vec3 weighted = Vec3::Zero();
  for (size_t i = 0; i < shell.size(); ++i) {
    s.depths[i] = 0;
    const Vec3 p = R * shell[i].position + X_WT.position;
    if (!s.scene.inside(p)) continue;
    Vec3 closest = Vec3::Zero();
    double d = 0;
    if (!s.scene.closest(p, 2 * reserved->radius, closest, d) || !(d > 0)) continue;
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
  ++s.scene.counts().contactFrames;
  return result;
}

size_t EmbreeVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  if (!reserved || s.scene.empty()) return 0;
  return s.scene.trianglesWithin(X_WT.position, reserved->radius);
}

SweepResult EmbreeVoxelBackend::sweep(const SweepQuery& query) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(query.shell);
  return s.scene.sweepSphere(query, reserved ? reserved->radius : query.leadingRadius, s.scale());
}

bool EmbreeVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  return reserved && s.scene.overlapsSphere(X_WT.position, reserved->radius, s.scale());
}

std::optional<SurfaceHit> EmbreeVoxelBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                      double maxDistance) const {
  return m_state->scene.raycast(origin, direction, maxDistance);
}

void EmbreeVoxelBackend::dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
  State& s = *m_state;
  if (s.scene.empty()) return;
  const std::vector<size_t> changed = s.surface.update(*s.data.grid, first, last, s.data.grid->cellsWithoutSurface());
  s.scene.rebuildBlocks(changed);
}

void EmbreeVoxelBackend::reportCounters(std::vector<Counter>& counters) const {
  m_state->scene.reportCounters(counters);
}

}  // namespace trephine::embree
