#include "plugins/embree/EmbreeEngine.h"

#include <algorithm>

#include "framework/geometry/MeshSphereContact.h"
#include "plugins/embree/EmbreeScene.h"

namespace trephine::embree {

struct EmbreeEngine::State {
  EmbreeScene scene;
  ReservedShells shells;
  mutable std::vector<double> depths;  // per shell point, the point-by-point contact
  mutable std::vector<Vec3> normals;
};

EmbreeEngine::EmbreeEngine() : m_state(std::make_unique<State>()) {}
EmbreeEngine::~EmbreeEngine() = default;

void EmbreeEngine::build(const TriangleBlocks& blocks, double deformationMargin) {
  m_state->scene.build(blocks, deformationMargin > 0);
}

void EmbreeEngine::rebuildBlocks(std::span<const size_t> changed) { m_state->scene.rebuildBlocks(changed); }

void EmbreeEngine::moveVertices(size_t block, bool rebuild) { m_state->scene.moveVertices(block, rebuild); }

bool EmbreeEngine::empty() const { return m_state->scene.empty(); }

MeshSurfaceCounters& EmbreeEngine::counts() { return m_state->scene.counts(); }

ShellSupport EmbreeEngine::reserveShell(std::span<const ShellPoint> shell) {
  State& s = *m_state;
  const ReservedShell& reserved = s.shells.add(shell);
  s.depths.resize(std::max(s.depths.size(), shell.size()));
  s.normals.resize(std::max(s.normals.size(), shell.size()));
  return reserved.sphere ? ShellSupport::kSphere : ShellSupport::kPointwise;
}

TriangleContact EmbreeEngine::contact(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  TriangleContact result;
  const ReservedShell* reserved = s.shells.find(shell);
  if (!reserved || s.scene.empty()) return result;
  if (reserved->sphere) {
    result.contact = s.scene.sphereContact(X_WT, shell, reserved->radius, &result.nearest, &result.nearestPoint);
    return result;
  }
  ShellContact& contact = result.contact;
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  Vec3 weighted = Vec3::Zero();
  double deepest = 0;  // mm: the deepest point's triangle is where the contact acts (a brain's force sites)
  for (size_t i = 0; i < shell.size(); ++i) {
    s.depths[i] = 0;
    const Vec3 p = R * shell[i].position + X_WT.position;
    if (!s.scene.inside(p)) continue;
    Vec3 closest = Vec3::Zero();
    double d = 0;
    TriangleRef which;
    if (!s.scene.closest(p, 2 * reserved->radius, closest, d, nullptr, &which) || !(d > 0)) continue;
    s.depths[i] = d;
    s.normals[i] = (closest - p) / d;
    weighted += d * s.normals[i];
    ++contact.points;
    if (d > deepest) deepest = d, result.nearest = which, result.nearestPoint = closest;
  }
  if (contact.points == 0) return result;
  contact.normal = weighted.norm() > 1e-12 ? Vec3(weighted.normalized()) : Vec3::Zero();
  for (size_t i = 0; i < shell.size(); ++i)
    if (s.depths[i] > 0)
      contact.penetration =
          std::max(contact.penetration, s.depths[i] * std::max(0.0, s.normals[i].dot(contact.normal)));
  contact.primitives = contact.points;
  s.scene.countContactFrame();
  return result;
}

size_t EmbreeEngine::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  if (!reserved || s.scene.empty()) return 0;
  return s.scene.trianglesWithin(X_WT.position, reserved->radius);
}

SweepResult EmbreeEngine::sweep(const SweepQuery& query, const SphereQueryScale& scale) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(query.shell);
  // A sphere shell sweeps itself; any other, its leading sphere (the burr of a capsule).
  return s.scene.sweepSphere(query, reserved && reserved->sphere ? reserved->radius : query.leadingRadius, scale);
}

bool EmbreeEngine::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell, const SphereQueryScale& scale) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  if (!reserved) return false;
  if (reserved->sphere) return s.scene.overlapsSphere(X_WT.position, reserved->radius, scale);
  // Any other shell, point by point (as its contact): a point inside the
  // solid by more than the inset. The sphere through its farthest point (a
  // capsule's shaft end) would overlap whatever lies within the shaft's length.
  const Eigen::Matrix3d R = X_WT.orientation.toRotationMatrix();
  for (const ShellPoint& point : shell) {
    const Vec3 p = R * point.position + X_WT.position;
    Vec3 closest = Vec3::Zero();
    double d = 0;
    if (s.scene.inside(p) && !(scale.inset > 0 && s.scene.closest(p, scale.inset, closest, d))) return true;
  }
  return false;
}

std::optional<SurfaceHit> EmbreeEngine::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  return m_state->scene.raycast(origin, direction, maxDistance);
}

void EmbreeEngine::reportCounters(std::vector<Counter>& counters) const { m_state->scene.reportCounters(counters); }

}  // namespace trephine::embree
