#include "plugins/voxel_skull/SkullSurfaceRebuild.h"

#include <algorithm>
#include <chrono>

#include "framework/core/Lifecycle.h"
#include "plugins/voxel_skull/MeshVoxelBackend.h"

namespace trephine::voxel {

namespace {
// A drill frame lowers at most a few thousand codes (a 466-point burr's
// footprint); the ring holds some 250 frames of that, so a rebuild of a
// second or more on a loaded machine loses nothing.
constexpr size_t kEditCapacity = size_t(1) << 20;
}  // namespace

void SkullSurfaceRebuild::init(InitContext& context) {
  VoxelSkull& skull = *l_skull;
  m_backend = skull.meshBackend();
  if (!m_backend) {
    context.note(l_skull, "rebuilds a mesh back-end's surface; " + skull.path() +
                              " uses the native back-end, which reads the drilled codes themselves, so this "
                              "component does nothing");
    m_idle = true;
    return;
  }
  if (!skull.drills()) {
    context.note(l_skull, skull.path() + " does not drill (drill=\"false\"): its surface never changes, so this "
                                         "component does nothing");
    m_idle = true;
    return;
  }
  if (auto error = skull.followSurfaceRebuild(*this, context.channels())) {
    context.error(l_skull, *error);
    return;
  }
  const SolidGrid& grid = skull.grid();
  m_codes.assign(grid.codes, grid.codes + grid.voxelCount());
  m_grid = grid;
  m_grid.codes = m_codes.data();
  m_grid.edits.clear();
  m_grid.buildOccupancy();
  m_edits = std::make_shared<ChangeQueue<VoxelEdit>>(kEditCapacity);
  skull.recordEdits(m_edits);
  m_backend->keepSecondCopy();
  for (auto& dirty : m_dirty) dirty.assign(m_backend->surface(0).blockCount(), 0);
  m_blocks.reserve(m_backend->surface(0).blockCount());
  m_ready = &context.channels().publish<SurfaceCopy>(*this, kSurfaceReadyChannel);
  m_inUse = context.channels().subscribe<SurfaceCopy>(skull, kSurfaceInUseChannel);
}

void SkullSurfaceRebuild::followEdits() {
  const BlockedIsoSurface& surface = m_backend->surface(0);
  m_editsFollowed += m_edits->drain([&](const VoxelEdit& edit) {
    const VoxelCode before = m_codes[size_t(edit.voxel)];
    m_codes[size_t(edit.voxel)] = edit.code;
    m_grid.noteLowered(edit.voxel, edit.code, before);
    const int64_t i = edit.voxel % m_grid.nx, j = (edit.voxel / m_grid.nx) % m_grid.ny,
                  k = edit.voxel / (int64_t(m_grid.nx) * m_grid.ny);
    surface.forBlocksTouching({i, j, k}, {i, j, k}, [&](size_t b) { m_dirty[0][b] = m_dirty[1][b] = 1; });
  });
}

void SkullSurfaceRebuild::tick(const TickContext&) {
  if (m_idle || !m_backend) return;
  followEdits();
  // The copy published last must be the one the haptic loop queries: only
  // then is the other one free.
  m_inUse->fetch();
  if (m_inUse->read().version != m_published.version) return;
  const int idle = 1 - m_published.copy;
  std::vector<uint8_t>& dirty = m_dirty[size_t(idle)];
  m_blocks.clear();
  for (size_t b = 0; b < dirty.size(); ++b)
    if (dirty[b]) m_blocks.push_back(b), dirty[b] = 0;
  if (m_blocks.empty()) return;
  // This group's own thread: re-extracting and building allocate, which the
  // haptic loop never does.
  const auto start = std::chrono::steady_clock::now();
  m_backend->rebuildCopy(idle, m_grid, m_grid.cellsWithoutSurface(), m_blocks);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  m_published = {m_published.version + 1, idle};
  m_ready->publish(m_published);
  m_rebuildMs += ms;
  m_longestRebuildMs = std::max(m_longestRebuildMs, ms);
  ++m_rebuilds;
}

void SkullSurfaceRebuild::finish(FinishContext& context) {
  if (m_edits && m_edits->dropped())
    context.error(*this, "fell behind the drill: " + std::to_string(m_edits->dropped()) +
                             " code changes did not fit its queue, so the mesh back-end's surface missed them; "
                             "raise this component's rate");
}

void SkullSurfaceRebuild::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"idle", m_idle ? 1.0 : 0.0});  // the native back-end, or no drill: nothing to rebuild
  counters.push_back({"rebuilds", double(m_rebuilds)});
  counters.push_back({"rebuild_ms", m_rebuildMs});  // summed: re-extraction and the library's rebuild
  counters.push_back({"longest_rebuild_ms", m_longestRebuildMs});
  counters.push_back({"edits_followed", double(m_editsFollowed)});
  if (m_edits) counters.push_back({"edits_dropped", double(m_edits->dropped())});
}

}  // namespace trephine::voxel
