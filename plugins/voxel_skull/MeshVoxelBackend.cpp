#include "plugins/voxel_skull/MeshVoxelBackend.h"

#include <chrono>
#include <stdexcept>

namespace trephine::voxel {

MeshVoxelBackend::MeshVoxelBackend(std::unique_ptr<TriangleEngine> engine) : m_engine(std::move(engine)) {
  if (!m_engine) throw std::invalid_argument("MeshVoxelBackend needs a triangle engine");
}

std::string MeshVoxelBackend::owner() const { return "backend=\"" + std::string(m_engine->name()) + "\""; }

SphereQueryScale MeshVoxelBackend::scale() const {
  const double side = m_data.grid->smallestSide();
  return {0.1 * side, 0.5 * side, m_data.grid->spacing.maxCoeff()};
}

void MeshVoxelBackend::bind(const VoxelData& data) {
  if (!data.grid->smooth) throw std::runtime_error(owner() + " meshes the smooth surface: set surface=\"smooth\"");
  const auto start = std::chrono::steady_clock::now();
  m_data = data;
  m_surface.build(*data.grid, data.grid->cellsWithoutSurface());
  m_engine->build(m_surface, 0.0);
  // The build time counts the extraction too.
  m_engine->counts().buildMs =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void MeshVoxelBackend::reserveShell(std::span<const ShellPoint> shell) { m_engine->reserveShell(shell); }

void MeshVoxelBackend::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
  m_engine->describeTool(shell, solid, owner());
}

VoxelContact MeshVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  VoxelContact result;
  result.contact = m_engine->contact(X_WT, shell).contact;
  return result;
}

size_t MeshVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  return m_engine->broadPhase(X_WT, shell);
}

SweepResult MeshVoxelBackend::sweep(const SweepQuery& query) const { return m_engine->sweep(query, scale()); }

bool MeshVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  return m_engine->overlaps(X_WT, shell, scale());
}

std::optional<SurfaceHit> MeshVoxelBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                    double maxDistance) const {
  return m_engine->raycast(origin, direction, maxDistance);
}

void MeshVoxelBackend::dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
  if (m_engine->empty()) return;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<size_t> changed = m_surface.update(*m_data.grid, first, last, m_data.grid->cellsWithoutSurface());
  m_engine->counts().extractMs +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  m_engine->rebuildBlocks(changed);
}

void MeshVoxelBackend::reportCounters(std::vector<Counter>& counters) const { m_engine->reportCounters(counters); }

}  // namespace trephine::voxel
