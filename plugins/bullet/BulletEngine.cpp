#include "plugins/bullet/BulletEngine.h"

#include "plugins/bullet/BulletScene.h"

namespace trephine::bullet {

struct BulletEngine::State {
  BulletScene scene;
  BulletTools tools;
};

BulletEngine::BulletEngine() : m_state(std::make_unique<State>()) {}
BulletEngine::~BulletEngine() = default;

void BulletEngine::build(const TriangleBlocks& blocks, double deformationMargin) {
  m_state->scene.build(blocks, deformationMargin);
}

void BulletEngine::rebuildBlocks(std::span<const size_t> changed) { m_state->scene.rebuildBlocks(changed); }

void BulletEngine::moveVertices(size_t block, bool rebuild) { m_state->scene.moveVertices(block, rebuild); }

bool BulletEngine::empty() const { return m_state->scene.empty(); }

MeshSurfaceCounters& BulletEngine::counts() { return m_state->scene.counts(); }

ShellSupport BulletEngine::reserveShell(std::span<const ShellPoint> shell) {
  return m_state->tools.reserve(shell) ? ShellSupport::kSphere : ShellSupport::kSolid;
}

void BulletEngine::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid, const std::string& owner) {
  m_state->tools.describe(shell, solid, owner);
}

TriangleContact BulletEngine::contact(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  TriangleContact result;
  const auto tool = s.tools.find(shell);
  if (!tool) return result;
  ClosestTriangle nearest;
  result.contact = s.scene.toolContact(X_WT, shell, tool->radius, tool->shaft, &nearest);
  if (nearest.found()) {
    result.nearest = nearest.which;
    result.nearestPoint = nearest.point;
  }
  return result;
}

size_t BulletEngine::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const auto tool = s.tools.find(shell);
  return tool ? s.scene.trianglesWithin(X_WT.position, tool->radius) : 0;
}

SweepResult BulletEngine::sweep(const SweepQuery& query, const SphereQueryScale& scale) const {
  const State& s = *m_state;
  const auto tool = s.tools.find(query.shell);
  return s.scene.sweepSphere(query, tool ? tool->radius : query.leadingRadius, scale.skin);
}

bool BulletEngine::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell, const SphereQueryScale& scale) const {
  const State& s = *m_state;
  const auto tool = s.tools.find(shell);
  return tool && s.scene.overlapsSphere(X_WT.position, tool->radius, scale.inset);
}

std::optional<SurfaceHit> BulletEngine::raycast(const Vec3& origin, const Vec3& direction, double maxDistance) const {
  return m_state->scene.raycast(origin, direction, maxDistance);
}

void BulletEngine::reportCounters(std::vector<Counter>& counters) const { m_state->scene.reportCounters(counters); }

}  // namespace trephine::bullet
