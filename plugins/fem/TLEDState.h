#pragma once
// What a TLEDModel moves (MuJoCo's mjData to its mjModel): the nodal
// displacements now and one step ago, the loads on the nodes (external
// forces, a node's own damping), and the step counts. The model is fixed
// while a state steps on it; it must outlive its states. States are values:
// a copy replays the steps after it exactly, and two states of one model
// move independently.
//
// Units as the model's (TLEDModel.h): mm, kg, s, forces in mN.
#include <cstdint>
#include <span>
#include <vector>

#include "plugins/fem/TLEDModel.h"

namespace trephine::fem {

class TLEDState {
 public:
  // At rest: every displacement zero, the held axes at their values, no load.
  explicit TLEDState(const TLEDModel& model);
  // Copies keep room for a load on every node (setting one never allocates).
  TLEDState(const TLEDState& other);
  TLEDState& operator=(const TLEDState& other);

  const TLEDModel& model() const { return *m_model; }

  // Advances one time step of the model. Allocation-free. A state at rest
  // (as made, or after resetToRest()) with no load (no external force, no
  // body acceleration, every held axis at zero) stays at rest without
  // computing anything until a load appears.
  void step();
  uint64_t steps() const { return m_steps; }
  uint64_t restingSteps() const { return m_restingSteps; }  // of steps(): at rest, not computed
  bool resting() const { return m_resting; }                // exactly at rest, and the last step found no load

  // External force on a node (mN) for the next steps, until changed or cleared.
  void setExternalForce(int32_t node, const Vec3& force_mN);
  void clearExternalForces();
  // Viscous damping on one node (kg/s, that is mN s/mm or N s/m) on top of
  // the mass-proportional damping, for the next steps until changed; 0
  // removes it. Central in velocity like the mass-proportional damping, so
  // stable at any value. Allocation-free.
  void setNodeDamping(int32_t node, double damping);
  size_t dampedNodes() const { return m_nodeDamping.size(); }

  // Displacements, mm.
  Vec3 displacement(int32_t node) const {
    const double* u = &m_u[m_model->index(node, 0)];
    return {u[0], u[1], u[2]};
  }
  Vec3 position(int32_t node) const { return m_model->m_rest[node] + displacement(node); }
  // Sets the displacement of every node now and one step ago (mm): a start
  // with a velocity (u - uPrevious) / dt. Held axes keep their values.
  void setDisplacements(std::span<const Vec3> u, std::span<const Vec3> uPrevious);
  // Back to rest, at rest (the held axes at their values); the external
  // forces stay. Allocation-free.
  void resetToRest();
  // Writes rest + displacement into `positions` (nodeCount() entries, holding
  // the shape written before); returns the largest displacement from rest and
  // the largest move from the shape before (mm), both infinite when any
  // position is not finite. Allocation-free.
  struct WrittenShape {
    double largestDisplacement = 0;  // mm, from rest
    double largestMove = 0;          // mm, from what `positions` held
  };
  WrittenShape writePositions(std::span<Vec3> positions) const;

  // The internal force on every node (mN) at the current displacements.
  void internalForces(std::span<Vec3> forces) const;
  // Energies, uJ: kinetic from the velocity at the half step just taken,
  // strain from the neo-Hookean energy of every element (slow: reports and tests).
  double kineticEnergy() const;
  double strainEnergy() const;
  // The von Mises equivalent of each element's true stress (kPa), one per
  // element in the mesh's order, into `out` (elementCount() entries): of the
  // elements the model holds at internal places [first, first + count) (the
  // whole mesh by default; a caller spreading the work over several ticks
  // takes it in slices). Several steps' cost for the whole mesh: for
  // viewers, at their rate. Allocation-free.
  void vonMisesStress(std::span<float> out, size_t first = 0, size_t count = SIZE_MAX) const;

  // Running totals of the element loop.
  const ElementStepCounts& counts() const { return m_counts; }
  // Elements with J <= 0 in the last step.
  uint64_t invertedNow() const { return m_invertedNow; }

 private:
  bool loaded() const;
  Mat3 deformationGradient(size_t k) const;  // of internal element k  // a force, an acceleration or a held displacement would move it from rest

  const TLEDModel* m_model = nullptr;
  // kNodeStride doubles per internal node:
  std::vector<double> m_u, m_uPrev;  // mm, now and one step ago
  mutable std::vector<double> m_f;   // mN, the step's internal less external forces
  struct ExternalForce {
    int32_t node;  // internal
    Vec3 force;    // mN
  };
  std::vector<ExternalForce> m_externalForces;  // reserved for every node
  std::vector<int32_t> m_externalSlot;          // per internal node: its entry, or -1
  struct NodeDamping {
    int32_t node;                // internal
    double damping;              // kg/s
    double before[kNodeStride];  // mm, u- during a step
  };
  std::vector<NodeDamping> m_nodeDamping;  // reserved for every node
  std::vector<int32_t> m_dampingSlot;      // per internal node: its entry, or -1
  uint64_t m_steps = 0, m_invertedNow = 0, m_restingSteps = 0;
  bool m_resting = true;  // exactly at rest: u = u- = 0
  ElementStepCounts m_counts;
};

}  // namespace trephine::fem
