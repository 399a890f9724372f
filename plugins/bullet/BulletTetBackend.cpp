#include "plugins/bullet/BulletTetBackend.h"

#include <chrono>
#include <stdexcept>

#include "framework/core/Component.h"
#include "framework/geometry/MeshSphereContact.h"
#include "plugins/bullet/BulletScene.h"
#include "plugins/tetra_brain/MeshTetRules.h"

namespace trephine::bullet {

struct BulletTetBackend::State {
  tetra::TetData data;
  tetra::BoundarySurface surface;
  BulletScene scene;
  BulletTools tools;
  tetra::RefitPolicy refit;
  tetra::FollowTiming following;
  ContactSite site;  // the last contact's
};

BulletTetBackend::BulletTetBackend() : m_state(std::make_unique<State>()) {}
BulletTetBackend::~BulletTetBackend() = default;

void BulletTetBackend::bind(const tetra::TetData& data) {
  State& s = *m_state;
  const auto start = std::chrono::steady_clock::now();
  s.data = data;
  s.surface.build(*data.mesh, *data.topology);
  if (s.surface.block(0).triangles.empty()) throw std::runtime_error("the mesh has no boundary faces");
  s.refit = tetra::RefitPolicy(tetra::refitMargin(s.surface));
  s.scene.build(s.surface, data.options.deformable ? s.refit.margin() : 0.0);
  s.scene.counts().buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void BulletTetBackend::reserveShell(std::span<const ShellPoint> shell) { m_state->tools.reserve(shell); }

void BulletTetBackend::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
  m_state->tools.describe(shell, solid, "backend=\"bullet\" of TetraBrain");
}

void BulletTetBackend::moveNodes(const tetra::NodeFrame& frame) {
  State& s = *m_state;
  const auto start = std::chrono::steady_clock::now();
  s.surface.moveTo(frame.nodes);  // in place: Bullet reads these arrays
  s.scene.moveVertices(0, s.refit.rebuild(frame.displacementBound));
  s.following.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
}

tetra::TetContact BulletTetBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool wantSites) {
  State& s = *m_state;
  tetra::TetContact result;
  const auto tool = s.tools.find(shell);
  if (!tool) return result;
  ClosestTriangle nearest;
  result.contact = s.scene.toolContact(X_WT, shell, tool->radius, tool->shaft, &nearest);
  if (wantSites && result.contact.points > 0 && nearest.found()) {
    s.site = tetra::siteAt(s.surface, nearest.which, nearest.point, result.contact.penetration);
    result.sites = {&s.site, 1};
  }
  return result;
}

size_t BulletTetBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const State& s = *m_state;
  const auto tool = s.tools.find(shell);
  return tool ? s.scene.trianglesWithin(X_WT.position, tool->radius) : 0;
}

SweepResult BulletTetBackend::sweep(const SweepQuery& query) const {
  const State& s = *m_state;
  const auto tool = s.tools.find(query.shell);
  // The proxy rests contactDepth deep, as on the native back-end.
  return s.scene.sweepSphere(query, tool ? tool->radius : query.leadingRadius, s.data.options.contactDepth);
}

bool BulletTetBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const auto tool = s.tools.find(shell);
  // Visibly in: ten contact depths in (as native).
  return tool && s.scene.overlapsSphere(X_WT.position, tool->radius, 10 * s.data.options.contactDepth);
}

std::optional<SurfaceHit> BulletTetBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                    double maxDistance) const {
  return m_state->scene.raycast(origin, direction, maxDistance);
}

void BulletTetBackend::reportCounters(std::vector<Counter>& counters) const {
  m_state->scene.reportCounters(counters);
  if (!m_state->data.options.deformable) return;
  counters.push_back({"refit_margin_mm", m_state->refit.margin()});
  m_state->following.report(counters);
}

}  // namespace trephine::bullet
