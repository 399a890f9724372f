#include "plugins/tetra_brain/TetGridRebuild.h"

#include <algorithm>
#include <chrono>

#include "framework/core/Lifecycle.h"
#include "plugins/tetra_brain/NativeTetBackend.h"

namespace trephine::tetra {

void TetGridRebuild::init(InitContext& context) {
  TetraBrain& brain = *l_mesh;
  const auto* native = dynamic_cast<const NativeTetBackend*>(brain.backend());
  if (!native || !brain.backend()->adoptsGrids()) {
    // The same scene runs on every back-end (a study varies it): here there
    // is nothing to rebuild, and the component stays idle.
    context.note(l_mesh, "rebuilds the native back-end's grids; " + brain.path() +
                             " uses another back-end, which refits or rebuilds its own tree as the mesh deforms, so "
                             "this component does nothing");
    m_idle = true;
    return;
  }
  if (!brain.deformer()) {
    context.error(l_mesh, "nothing deforms " + brain.path() +
                              " before this component: place it after the deformation component (TLEDForceField, "
                              "ScriptedDeformation) in the scene");
    return;
  }
  m_mesh = &brain.mesh();
  m_native = native;
  m_margin = native->displacementMargin();
  if (!(m_margin > 0)) {
    context.error(l_mesh, "the grids of " + brain.path() + " have no displacement margin to rebuild within");
    return;
  }
  m_set = native->currentGrids();  // the rest grids: the reference the first drift is measured from
  m_positions = context.channels().subscribe<NodePositions>(*brain.deformer(), kNodePositionsChannel);
  m_channel = &context.channels().publish<TetGridSet>(*this, kGridsChannelName);
  if (auto error = brain.followGridRebuild(*this, context.channels())) context.error(l_mesh, *error);
}

void TetGridRebuild::tick(const TickContext&) {
  if (!m_positions || !m_positions->fetch()) return;
  const NodePositions& frame = m_positions->read();
  if (frame.positions.size() != m_mesh->nodeCount()) return;
  const double drift = driftFromReference(m_set, frame.positions);
  if (drift <= d_threshold.value() * m_margin) return;
  // This group's own thread: building allocates, which the haptic loop never does.
  const auto start = std::chrono::steady_clock::now();
  // The back-end's cell, final once initialisation ended (the tools' shells
  // may change it after this component's init).
  buildTetGrids(*m_mesh, m_native->faces(), frame.positions, m_margin, m_native->cellSize(), m_native->faceCellSize(),
                m_set);
  ++m_set.version;
  m_channel->publish(m_set);
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  m_longestBuildMs = std::max(m_longestBuildMs, ms);
  m_largestDrift = std::max(m_largestDrift, drift);
  ++m_rebuilds;
}

void TetGridRebuild::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"idle", m_idle ? 1.0 : 0.0});  // the brain's back-end keeps its own tree
  counters.push_back({"rebuilds", double(m_rebuilds)});
  counters.push_back({"longest_build_ms", m_longestBuildMs});
  counters.push_back({"largest_drift_mm", m_largestDrift});  // from the grids' shape when a rebuild began
}

}  // namespace trephine::tetra
