#include "plugins/bullet/BulletVoxelBackend.h"

#include <chrono>
#include <stdexcept>

#include "framework/geometry/MeshSphereContact.h"
#include "plugins/bullet/BulletScene.h"
#include "plugins/voxel_skull/IsoSurface.h"

namespace trephine::bullet {

struct BulletVoxelBackend::State {
  voxel::VoxelData data;
  voxel::BlockedIsoSurface surface;
  BulletScene scene;
  ReservedShells shells;
};

BulletVoxelBackend::BulletVoxelBackend() : m_state(std::make_unique<State>()) {}
BulletVoxelBackend::~BulletVoxelBackend() = default;

void BulletVoxelBackend::bind(const voxel::VoxelData& data) {
  State& s = *m_state;
  if (!data.grid->smooth)
    throw std::runtime_error("backend=\"bullet\" meshes the smooth surface: set surface=\"smooth\"");
  const auto start = std::chrono::steady_clock::now();
  s.data = data;
  s.surface.build(*data.grid);
  s.scene.build(s.surface);
  // The build time counts the extraction too.
  s.scene.counts().buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void BulletVoxelBackend::reserveShell(std::span<const ShellPoint> shell) {
  State& s = *m_state;
  if (!s.shells.add(shell).sphere)
    throw std::runtime_error(
        "backend=\"bullet\" takes a spherical burr (every shell point at one radius, as PointshellTool); this "
        "tool's shell is not a sphere");
}

voxel::VoxelContact BulletVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  const State& s = *m_state;
  voxel::VoxelContact result;
  if (const ReservedShell* reserved = s.shells.find(shell))
    result.contact = s.scene.sphereContact(X_WT, shell, reserved->radius);
  return result;
}

size_t BulletVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  return reserved ? s.scene.trianglesWithin(X_WT.position, reserved->radius) : 0;
}

SweepResult BulletVoxelBackend::sweep(const SweepQuery& query) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(query.shell);
  // The proxy rests a tenth of the smallest voxel side deep.
  return s.scene.sweepSphere(query, reserved ? reserved->radius : query.leadingRadius,
                             0.1 * s.data.grid->smallestSide());
}

bool BulletVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  const State& s = *m_state;
  const ReservedShell* reserved = s.shells.find(shell);
  // Visibly in: the sphere pulled one voxel in still reaches the bone.
  return reserved && s.scene.overlapsSphere(X_WT.position, reserved->radius, s.data.grid->spacing.maxCoeff());
}

std::optional<SurfaceHit> BulletVoxelBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                      double maxDistance) const {
  return m_state->scene.raycast(origin, direction, maxDistance);
}

void BulletVoxelBackend::dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
  State& s = *m_state;
  if (s.scene.empty()) return;
  s.scene.rebuildBlocks(s.surface.update(*s.data.grid, first, last));
}

void BulletVoxelBackend::reportCounters(std::vector<Counter>& counters) const {
  m_state->scene.reportCounters(counters);
}

}  // namespace trephine::bullet
