#include "plugins/bullet/BulletVoxelBackend.h"

#include <chrono>
#include <stdexcept>

#include "framework/geometry/MeshSphereContact.h"
#include "plugins/bullet/BulletScene.h"
#include "framework/data/IsoSurface.h"

namespace trephine::bullet {

struct BulletVoxelBackend::State {
  voxel::VoxelData data;
  BlockedIsoSurface surface;
  BulletScene scene;
  BulletTools tools;
};

BulletVoxelBackend::BulletVoxelBackend() : m_state(std::make_unique<State>()) {}
BulletVoxelBackend::~BulletVoxelBackend() = default;

void BulletVoxelBackend::bind(const voxel::VoxelData& data) {
  State& s = *m_state;
  if (!data.grid->smooth)
    throw std::runtime_error("backend=\"bullet\" meshes the smooth surface: set surface=\"smooth\"");
  const auto start = std::chrono::steady_clock::now();
  s.data = data;
  s.surface.build(*data.grid, data.grid->cellsWithoutSurface());
  s.scene.build(s.surface);
  // The build time counts the extraction too.
  s.scene.counts().buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void BulletVoxelBackend::reserveShell(std::span<const ShellPoint> shell) { m_state->tools.reserve(shell); }

void BulletVoxelBackend::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
  m_state->tools.describe(shell, solid, "backend=\"bullet\"");
}

voxel::VoxelContact BulletVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  const State& s = *m_state;
  voxel::VoxelContact result;
  if (const auto tool = s.tools.find(shell))
    result.contact = s.scene.toolContact(X_WT, shell, tool->radius, tool->shaft);
  return result;
}

size_t BulletVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const State& s = *m_state;
  const auto tool = s.tools.find(shell);
  return tool ? s.scene.trianglesWithin(X_WT.position, tool->radius) : 0;
}

SweepResult BulletVoxelBackend::sweep(const SweepQuery& query) const {
  const State& s = *m_state;
  const auto tool = s.tools.find(query.shell);
  // The proxy rests a tenth of the smallest voxel side deep.
  return s.scene.sweepSphere(query, tool ? tool->radius : query.leadingRadius, 0.1 * s.data.grid->smallestSide());
}

bool BulletVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const auto tool = s.tools.find(shell);
  // Visibly in: the sphere pulled one voxel in still reaches the bone.
  return tool && s.scene.overlapsSphere(X_WT.position, tool->radius, s.data.grid->spacing.maxCoeff());
}

std::optional<SurfaceHit> BulletVoxelBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                      double maxDistance) const {
  return m_state->scene.raycast(origin, direction, maxDistance);
}

void BulletVoxelBackend::dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
  State& s = *m_state;
  if (s.scene.empty()) return;
  s.scene.rebuildBlocks(s.surface.update(*s.data.grid, first, last, s.data.grid->cellsWithoutSurface()));
}

void BulletVoxelBackend::reportCounters(std::vector<Counter>& counters) const {
  m_state->scene.reportCounters(counters);
}

}  // namespace trephine::bullet
