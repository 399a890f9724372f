#pragma once
// The removal law of a resected brain, and what it measures. Each haptic
// frame, every tool whose tissue action is engaged puts its power into the
// tetrahedra it touches (shared equally among them):
//  - an aspirator (TissueAction::kAspirate) at P = min(rated power, coupling
//    F v_tip) for a contact force F: a tetrahedron is removed once the energy
//    it took reaches its volume times its tissue's removalEnergy, so the
//    volume rate is P / removalEnergy and follows the force the hand applies,
//    as the drilling of the skull does;
//  - a bipolar forceps (kCoagulate) at its power: a tetrahedron is coagulated
//    once it took its volume times kCoagulationEnergy, and then does not
//    bleed when removed.
// Only the tetrahedra of a declared, non-critical tissue are removed; a tool
// touching a critical one is counted (time on critical tissue) whether its
// action is engaged or not. Removing an uncoagulated tetrahedron loses its
// volume times its tissue's vascularity in blood.
//
// Everything is sized at build(): act() and removed() never allocate (the
// haptic loop calls them).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "framework/data/TetMesh.h"
#include "framework/geometry/ShellContactTarget.h"
#include "plugins/tetra_brain/TissueTable.h"

namespace trephine::tetra {

// J/mm^3 to coagulate tissue: heating it from 37 to about 70 degrees C at a
// volumetric heat capacity of 3.6e-3 J/(mm^3 K) (water-like soft tissue).
inline constexpr double kCoagulationEnergy = 0.12;

// What the law has measured so far, by tissue (TissueTable's order).
struct ResectionTotals {
  std::vector<double> volume_mm3;       // at rest, per tissue
  std::vector<double> removed_mm3;      // per tissue
  std::vector<double> coagulated_mm3;   // per tissue
  double bloodLoss_ml = 0;
  double criticalContact_s = 0;         // time some tool touched critical tissue
  uint64_t removedTets = 0;
  uint64_t criticalContacts = 0;        // stretches of contact with critical tissue
  double energyIn_J = 0;                // put in by aspirators
};

class TissueRemoval {
 public:
  // Per tetrahedron: its volume, tissue and thresholds. Allocates.
  void build(const TetMesh& mesh, const TissueTable& tissues);
  bool built() const { return !m_volume.empty(); }

  // One frame's responses (in their fixed order). Tetrahedra whose energy
  // reached their threshold are appended to `toRemove` (within its capacity,
  // each once); returns whether a tool touched critical tissue this frame.
  bool act(std::span<const ContactResponse> responses, std::vector<int32_t>& toRemove);
  // The tetrahedra a removal took (RemainingMesh's answer): their volume and blood.
  void removed(std::span<const int32_t> tets);

  const ResectionTotals& totals() const { return m_totals; }
  // The tissue index (TissueTable order) of a tetrahedron, or -1 for an undeclared label.
  int32_t tissueOf(int32_t tet) const { return m_tissue[size_t(tet)]; }
  bool coagulated(int32_t tet) const { return m_coagulation[size_t(tet)] >= m_coagulationNeeded[size_t(tet)]; }
  bool removable(int32_t tet) const { return m_removalNeeded[size_t(tet)] > 0; }

 private:
  std::vector<double> m_volume;             // mm^3
  std::vector<int32_t> m_tissue;            // index, or -1
  std::vector<double> m_removalNeeded;      // J, 0: never removed (undeclared or critical)
  std::vector<double> m_coagulationNeeded;  // J
  std::vector<double> m_energy;             // J taken by an aspirator so far
  std::vector<double> m_coagulation;        // J taken by a bipolar so far
  std::vector<uint8_t> m_queued;            // already in a removal list
  std::vector<uint8_t> m_critical;          // per tissue
  std::vector<double> m_vascularity;        // per tissue, ml/ml
  ResectionTotals m_totals;
  bool m_touchingCritical = false;          // last frame
};

}  // namespace trephine::tetra
