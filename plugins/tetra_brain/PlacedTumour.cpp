#include "plugins/tetra_brain/PlacedTumour.h"

#include "framework/core/Lifecycle.h"

namespace trephine::tetra {

void PlacedTumour::init(InitContext& context) {
  TetraBrain& brain = *l_mesh;
  if (brain.mesh().tetCount() == 0) return;  // the mesh did not load: its own error says why
  const TetraBrain::PlacedRegion placed = brain.labelBall(d_center.value(), d_radius.value(), d_label.value());
  if (!placed.error.empty()) {
    context.error(placed.atLabel ? static_cast<const BaseField&>(d_label) : d_center, placed.error);
    return;
  }
  m_tets = placed.tets;
  m_volume = placed.volume;
}

void PlacedTumour::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"tetrahedra", double(m_tets)});
  counters.push_back({"volume_mm3", m_volume});
}

}  // namespace trephine::tetra
