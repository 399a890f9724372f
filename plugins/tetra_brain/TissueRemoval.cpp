#include "plugins/tetra_brain/TissueRemoval.h"

#include <cmath>

namespace trephine::tetra {

void TissueRemoval::build(const TetMesh& mesh, const TissueTable& tissues) {
  const size_t n = mesh.tetCount();
  m_volume.resize(n);
  m_tissue.assign(n, -1);
  m_removalNeeded.assign(n, 0.0);
  m_coagulationNeeded.assign(n, 0.0);
  m_energy.assign(n, 0.0);
  m_coagulation.assign(n, 0.0);
  m_queued.assign(n, 0);
  const auto& specs = tissues.tissues();
  m_critical.assign(specs.size(), 0);
  m_vascularity.assign(specs.size(), 0.0);
  m_totals = {};
  m_totals.volume_mm3.assign(specs.size(), 0.0);
  m_totals.removed_mm3.assign(specs.size(), 0.0);
  m_totals.coagulated_mm3.assign(specs.size(), 0.0);
  for (size_t i = 0; i < specs.size(); ++i) {
    m_critical[i] = specs[i].critical;
    m_vascularity[i] = specs[i].vascularity;
  }
  for (size_t t = 0; t < n; ++t) {
    const TetIndices& k = mesh.tets[t];
    m_volume[t] = std::abs(signedVolume(mesh.nodes[k[0]], mesh.nodes[k[1]], mesh.nodes[k[2]], mesh.nodes[k[3]]));
    m_coagulationNeeded[t] = m_volume[t] * kCoagulationEnergy;
    if (mesh.labels.empty()) continue;
    const TissueSpec* tissue = tissues.ofLabel(mesh.labels[t]);
    if (!tissue) continue;
    const int32_t index = int32_t(tissue - specs.data());
    m_tissue[t] = index;
    m_totals.volume_mm3[size_t(index)] += m_volume[t];
    if (!tissue->critical) m_removalNeeded[t] = m_volume[t] * tissue->removalEnergy;
  }
  m_touchingCritical = false;
}

bool TissueRemoval::act(std::span<const ContactResponse> responses, std::vector<int32_t>& toRemove) {
  bool critical = false;
  double dt = 0;
  for (const ContactResponse& response : responses) {
    dt = std::max(dt, response.load.dt);
    size_t touched = 0;
    for (int64_t tet : response.touched) {
      if (tet < 0 || size_t(tet) >= m_volume.size()) continue;
      const int32_t tissue = m_tissue[size_t(tet)];
      if (tissue >= 0 && m_critical[size_t(tissue)]) critical = true;
      ++touched;
    }
    const TissueAction& action = response.load.action;
    if (!response.cutting || action.kind == TissueAction::Kind::kNone || touched == 0) continue;
    const double force = response.load.force_N.allFinite() ? response.load.force_N.norm() : 0.0;
    const double energy = action.powerAt(force) * response.load.dt;  // J this frame
    if (!(energy > 0)) continue;
    const double share = energy / double(touched);
    for (int64_t t64 : response.touched) {
      if (t64 < 0 || size_t(t64) >= m_volume.size()) continue;
      const size_t tet = size_t(t64);
      if (action.kind == TissueAction::Kind::kCoagulate) {
        const bool was = m_coagulation[tet] >= m_coagulationNeeded[tet];
        m_coagulation[tet] += share;
        if (!was && m_coagulation[tet] >= m_coagulationNeeded[tet] && m_tissue[tet] >= 0)
          m_totals.coagulated_mm3[size_t(m_tissue[tet])] += m_volume[tet];
        continue;
      }
      if (!(m_removalNeeded[tet] > 0)) continue;  // undeclared or critical: never removed
      m_energy[tet] += share;
      m_totals.energyIn_J += share;
      if (m_energy[tet] >= m_removalNeeded[tet] && !m_queued[tet] && toRemove.size() < toRemove.capacity()) {
        m_queued[tet] = 1;
        toRemove.push_back(int32_t(tet));
      }
    }
  }
  if (critical) {
    m_totals.criticalContact_s += dt;
    if (!m_touchingCritical) ++m_totals.criticalContacts;
  }
  m_touchingCritical = critical;
  return critical;
}

void TissueRemoval::removed(std::span<const int32_t> tets) {
  for (int32_t t : tets) {
    const size_t tet = size_t(t);
    ++m_totals.removedTets;
    const int32_t tissue = m_tissue[tet];
    if (tissue < 0) continue;
    m_totals.removed_mm3[size_t(tissue)] += m_volume[tet];
    if (m_coagulation[tet] < m_coagulationNeeded[tet])
      m_totals.bloodLoss_ml += 1e-3 * m_volume[tet] * m_vascularity[size_t(tissue)];  // mm^3 to ml
  }
}

}  // namespace trephine::tetra
