#include "plugins/voxel_skull/MeshVoxelBackend.h"

#include <chrono>
#include <stdexcept>

namespace trephine::voxel {

namespace {
double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}
}  // namespace

MeshVoxelBackend::MeshVoxelBackend(std::unique_ptr<TriangleEngine> engine) {
  if (!engine) throw std::invalid_argument("MeshVoxelBackend needs a triangle engine");
  m_copies[0].engine = std::move(engine);
}

std::string MeshVoxelBackend::owner() const { return "backend=\"" + std::string(m_copies[0].engine->name()) + "\""; }

SphereQueryScale MeshVoxelBackend::scale() const {
  const double side = m_data.grid->smallestSide();
  return {0.1 * side, 0.5 * side, m_data.grid->spacing.maxCoeff()};
}

void MeshVoxelBackend::bind(const VoxelData& data) {
  if (!data.grid->smooth) throw std::runtime_error(owner() + " meshes the smooth surface: set surface=\"smooth\"");
  const auto start = std::chrono::steady_clock::now();
  m_data = data;
  m_current = 0;
  for (Copy& copy : m_copies) {
    if (!copy.engine) continue;
    copy.surface.build(*data.grid, data.grid->cellsWithoutSurface());
    copy.engine->build(copy.surface, 0.0);
  }
  // The build time counts the extraction too.
  m_copies[0].engine->counts().buildMs = msSince(start);
}

void MeshVoxelBackend::keepSecondCopy() {
  if (keepsSecondCopy()) return;
  if (!m_data.grid) throw std::logic_error("MeshVoxelBackend::keepSecondCopy before bind");
  const auto start = std::chrono::steady_clock::now();
  Copy& second = m_copies[1];
  second.engine = m_copies[0].engine->another();
  second.surface = m_copies[0].surface;
  second.engine->build(second.surface, 0.0);
  for (const auto shell : m_shells) second.engine->reserveShell(shell);
  for (const DescribedTool& tool : m_tools) second.engine->describeTool(tool.shell, tool.solid, owner());
  second.engine->counts().buildMs = msSince(start);
}

void MeshVoxelBackend::reserveShell(std::span<const ShellPoint> shell) {
  m_shells.push_back(shell);
  for (Copy& copy : m_copies)
    if (copy.engine) copy.engine->reserveShell(shell);
}

void MeshVoxelBackend::describeTool(std::span<const ShellPoint> shell, const ToolSolid& solid) {
  m_tools.push_back({shell, solid});
  for (Copy& copy : m_copies)
    if (copy.engine) copy.engine->describeTool(shell, solid, owner());
}

VoxelContact MeshVoxelBackend::collide(const Pose& X_WT, std::span<const ShellPoint> shell, bool) {
  VoxelContact result;
  result.contact = engine().contact(X_WT, shell).contact;
  return result;
}

size_t MeshVoxelBackend::broadPhase(const Pose& X_WT, std::span<const ShellPoint> shell) {
  return engine().broadPhase(X_WT, shell);
}

SweepResult MeshVoxelBackend::sweep(const SweepQuery& query) const { return engine().sweep(query, scale()); }

bool MeshVoxelBackend::overlaps(const Pose& X_WT, std::span<const ShellPoint> shell) const {
  return engine().overlaps(X_WT, shell, scale());
}

std::optional<SurfaceHit> MeshVoxelBackend::raycast(const Vec3& origin, const Vec3& direction,
                                                    double maxDistance) const {
  return engine().raycast(origin, direction, maxDistance);
}

void MeshVoxelBackend::dataChanged(const std::array<int64_t, 3>& first, const std::array<int64_t, 3>& last) {
  if (keepsSecondCopy() || m_copies[0].engine->empty()) return;
  Copy& only = m_copies[0];
  const auto start = std::chrono::steady_clock::now();
  const std::vector<size_t> changed = only.surface.update(*m_data.grid, first, last, m_data.grid->cellsWithoutSurface());
  only.engine->counts().extractMs += msSince(start);
  only.engine->rebuildBlocks(changed);
}

void MeshVoxelBackend::rebuildCopy(int copy, const VoxelGrid& grid, const CellsWithoutSurface& skip,
                                   std::span<const size_t> blocks) {
  Copy& target = m_copies[size_t(copy)];
  if (!target.engine || blocks.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  target.surface.reextract(grid, blocks, skip);
  target.engine->counts().extractMs += msSince(start);
  target.engine->rebuildBlocks(blocks);
}

void MeshVoxelBackend::adoptSurface(int copy) {
  if (copy == 0 || (copy == 1 && keepsSecondCopy())) m_current = copy;
}

void MeshVoxelBackend::reportCounters(std::vector<Counter>& counters) const {
  const size_t first = counters.size();
  m_copies[0].engine->reportCounters(counters);
  if (keepsSecondCopy()) {
    // Both copies' work together (the second's queries and builds were made
    // as the first's), but for the triangles: the copy in use.
    std::vector<Counter> second;
    m_copies[1].engine->reportCounters(second);
    for (const Counter& c : second)
      for (size_t i = first; i < counters.size(); ++i) {
        if (counters[i].name != c.name) continue;
        if (c.name != "triangles")
          counters[i].value += c.value;
        else if (m_current == 1)
          counters[i].value = c.value;
      }
  }
  counters.push_back({"surface_copies", keepsSecondCopy() ? 2.0 : 1.0});
}

}  // namespace trephine::voxel
