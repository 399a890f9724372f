#include "plugins/embree/EmbreeTetBackend.h"

#include <chrono>
#include <stdexcept>

#include "framework/core/Component.h"
#include "framework/geometry/MeshSphereContact.h"
#include "plugins/embree/EmbreeScene.h"
#include "plugins/tetra_brain/MeshTetRules.h"

namespace trephine::embree {

struct EmbreeTetBackend::State {
  tetra::TetData data;
  tetra::BoundarySurface surface;
  EmbreeScene scene;
  ReservedShells shells;
  tetra::RefitPolicy refit;
  tetra::FollowTiming following;
  ContactSite site;  // the last contact's

  // The proxy rests contactDepth deep (as on the native back-end); sweeps
  // sample the exact depth every half average edge; a displayed burr ten
  // contact depths in overlaps (as native).
  SphereQueryScale scale() const {
    const double skin = data.options.contactDepth;
    return {skin, 0.5 * surface.averageEdge(), 10 * skin};
  }
};

EmbreeTetBackend::EmbreeTetBackend() : m_state(std::make_unique<State>()) {}
EmbreeTetBackend::~EmbreeTetBackend() = default;

void EmbreeTetBackend::bind(const tetra::TetData& data) {
  State& s = *m_state;
  const auto start = std::chrono::steady_clock::now();
  s.data = data;
  s.surface.build(*data.mesh, *data.topology);
  if (s.surface.block(0).triangles.empty()) throw std::runtime_error("the mesh has no boundary faces");
  s.scene.build(s.surface, data.options.deformable);
  s.refit = tetra::RefitPolicy(tetra::refitMargin(s.surface));
  s.scene.counts().buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void EmbreeTetBackend::reserveShell(std::span<const ShellPoint> shell) {
  if (!m_state->shells.add(shell).sphere)
    throw std::runtime_error(
        "backend=\"embree\" of TetraBrain takes a spherical burr (every shell point at one radius, as "
        "PointshellTool); this tool's shell is not a sphere");
}

void EmbreeTetBackend::moveNodes(const tetra::NodeFrame& frame) {
  State& s = *m_state;
  const auto start = std::chrono::steady_clock::now();
  s.surface.moveTo(frame.nodes);
  s.scene.moveVertices(0, s.refit.rebuild(frame.displacementBound));
  s.following.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
}

tetra::TetContact EmbreeTetBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites) {
  State& s = *m_state;
  tetra::TetContact result;
  const ReservedShell* reserved = s.shells.find(shell);
  if (!reserved) return result;
  TriangleRef nearest;
  Vec3 point = Vec3::Zero();
  result.contact = s.scene.sphereContact(X_WT, shell, reserved->radius, &nearest, &point);
  if (wantSites && result.contact.points > 0 && nearest.valid()) {
    s.site = tetra::siteAt(s.surface, nearest, point, result.contact.penetration);
    result.sites = {&s.site, 1};
  }
  return result;
}

size_t EmbreeTetBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  return reserved ? s.scene.trianglesWithin(X_WT.position, reserved->radius) : 0;
}

SweepResult EmbreeTetBackend::sweep(const SweepQuery& query) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(query.shell);
  return s.scene.sweepSphere(query, reserved ? reserved->radius : query.leadingRadius, s.scale());
}

bool EmbreeTetBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  return reserved && s.scene.overlapsSphere(X_WT.position, reserved->radius, s.scale());
}

std::optional<SurfaceHit> EmbreeTetBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                    double maxDistance) const {
  return m_state->scene.raycast(origin, direction, maxDistance);
}

void EmbreeTetBackend::reportCounters(std::vector<Counter>& counters) const {
  m_state->scene.reportCounters(counters);
  if (!m_state->data.options.deformable) return;
  counters.push_back({"refit_margin_mm", m_state->refit.margin()});
  m_state->following.report(counters);
}

}  // namespace trephine::embree
