#pragma once
// Total Lagrangian Explicit Dynamics on linear tetrahedra (Miller, Joldes,
// Lance and Wittek 2007): the element matrices are computed once on the rest
// shape (shape-function derivatives and volumes), each step evaluates the
// deformation gradient of every element from the nodal displacements, the
// neo-Hookean stress (NeoHookean.h) and the internal nodal forces, and
// advances the displacements by central differences with lumped masses and
// mass-proportional damping:
//   u+ = (dt^2 / m (f_ext - f_int) + 2 u - (1 - a dt / 2) u-) / (1 + a dt / 2).
// Linear tetrahedra have one integration point and no hourglass modes.
//
// Units (mm, kg, s): lengths mm, density kg/mm^3, moduli kPa (kg / (mm s^2)),
// forces mN (kg mm / s^2), accelerations mm/s^2, energies uJ. The coupling
// with the haptic side, in newtons, converts (TLEDForceField).
//
// Storage is structure-of-arrays, elements and nodes alike, so that the
// element loop vectorises (TLEDKernel.cpp); nothing allocates after the
// model is built.
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "framework/math/Math.h"
#include "plugins/fem/NeoHookean.h"
#include "framework/data/TetMesh.h"

namespace trephine::fem {

struct ElementMaterial {
  double density = 1e-6;      // kg/mm^3 (1000 kg/m^3)
  double youngModulus = 30;   // kPa
  double poissonRatio = 0.3;  // below 0.5
};

// Per-step figures of the element loop.
struct ElementStepCounts {
  uint64_t inverted = 0;     // elements with J <= 0 (their isochoric stress is taken at J = kMinIsochoricJ)
  uint64_t farFromRest = 0;  // elements whose J^(-1/3) took the exact (slow) path
};

// Node vectors are stored four doubles per node (x, y, z and a zero), so that
// the element loop reaches a node's three coordinates in one cache line and
// the update loop is plain vector arithmetic.
inline constexpr size_t kNodeStride = 4;

// The precision of the element loop's arithmetic. Single: twice the vector
// lanes and half the bytes per element, forces to about 1e-7 of the stress
// (the node vectors stay in double).
enum class ElementPrecision { kDouble, kSingle };

// The instruction sets the element loop is compiled for. The best one this
// processor has is used; tests run the others against it.
enum class ElementLoopIsa { kPortable, kAvx2, kAvx512 };
bool elementLoopAvailable(ElementLoopIsa isa);
ElementLoopIsa bestElementLoopIsa();
const char* elementLoopName(ElementLoopIsa isa);

// The element arrays, structure of arrays, in the model's internal order (a
// space-filling curve, so that neighbouring elements share nodes in cache),
// padded to a multiple of kLanes with elements of zero volume on node 0.
struct TLEDElements {
  static constexpr size_t kLanes = 64;  // the element loop's chunk: every chunk is whole
  size_t count = 0;   // real elements
  size_t padded = 0;  // count rounded up to kLanes
  // Where the element's nodes are in the node vectors: kNodeStride times
  // their internal indices (a scaled index the element loop's addressing
  // takes as it is).
  std::vector<int32_t> nodeOffset[4];
  // Rest-shape derivatives of the shape functions of local nodes 1..3 (node 0's
  // are minus their sum), 1/mm: grad[3 * (a - 1) + j][e] = dN_a / dX_j.
  std::vector<double> grad[9];
  // The moduli times the rest volume (kPa mm^3 = uJ): the stress is linear in
  // them, and the force is the volume times the stress.
  std::vector<double> muVolume, kappaVolume;
  // The same in single precision, filled only for ElementPrecision::kSingle.
  ElementPrecision precision = ElementPrecision::kDouble;
  struct Single {
    std::vector<float> grad[9];
    std::vector<float> muVolume, kappaVolume;
  } single;
};

// Computes the internal nodal forces f_int (mN) of every element from the
// displacements `u` (mm), adding them into `f`; both kNodeStride doubles per
// internal node. `isa` must be available. Defined in TLEDKernel.cpp.
ElementStepCounts accumulateInternalForces(const TLEDElements& elements, const double* u, double* f,
                                           ElementLoopIsa isa);

// J below which the isochoric part of the stress is evaluated at this J
// instead: it grows as J^(-5/3) and an element squeezed flat (or inverted)
// would otherwise produce an unbounded force or a NaN. The volumetric part,
// kappa (J - 1) cof F, is polynomial and stays as it is: it pushes an inverted
// element back.
inline constexpr double kMinIsochoricJ = 0.05;

class TLEDModel {
 public:
  // Precomputes the element matrices and the lumped masses. `materials` has
  // one entry per tetrahedron, or one for all. Throws std::invalid_argument
  // for an element of non-positive rest volume (its index), or a material out
  // of range. Node and element indices in this interface are the mesh's.
  TLEDModel(std::span<const Vec3> restNodes, std::span<const TetIndices> tets,
            std::span<const ElementMaterial> materials);

  size_t nodeCount() const { return m_rest.size(); }
  size_t elementCount() const { return m_elements.count; }

  // The largest stable time step of central differences without damping (s):
  // the smallest, over the elements, of the element's characteristic length
  // over its dilatational wave speed, L / c with L = 1 / |grad N| (a regular
  // tetrahedron's is half its height). `criticalElement` sets it.
  double criticalTimeStep() const { return m_criticalStep; }
  size_t criticalElement() const { return m_criticalElement; }
  // With mass-proportional damping a (1/s) the bound is lowered to
  // dt_cr (sqrt(1 + xi^2) - xi), xi = a dt_cr / 4 at the highest frequency.
  double criticalTimeStep(double damping) const;
  // Elements whose own step is below `dt` (s).
  size_t elementsBelowStep(double dt) const;

  // Gives `elements` another material: their moduli, their share of the
  // lumped masses and the critical time step follow.
  void assignMaterial(std::span<const int32_t> elements, const ElementMaterial& material);
  // Selective mass scaling: raises the density of the elements whose own
  // critical step is below `dt` (s), each to the density that makes it dt, so
  // that the mesh is stable at dt; returns how many. The stiffness is
  // unchanged; the smallest elements respond more slowly. Starts from the
  // materials' densities each time (after assignMaterial, call it again).
  size_t scaleMassForStep(double dt);
  // Mass added by the scaling, kg.
  double addedMass() const;

  // The element loop's arithmetic (double by default). Allocates: at setup.
  void setElementPrecision(ElementPrecision precision);
  ElementPrecision elementPrecision() const { return m_elements.precision; }
  // The instruction set of the element loop (the best available by default);
  // throws std::invalid_argument for one this processor lacks.
  void setElementLoopIsa(ElementLoopIsa isa);
  ElementLoopIsa elementLoopIsa() const { return m_isa; }

  // Time step (s) and mass-proportional damping (1/s).
  void setTimeStep(double dt, double damping);
  double timeStep() const { return m_dt; }
  double damping() const { return m_damping; }

  // Uniform acceleration of every node (gravity), mm/s^2.
  void setBodyAcceleration(const Vec3& acceleration) { m_bodyAcceleration = acceleration; }
  // Holds `axes` (bit 0: x, 1: y, 2: z) of a node at its rest position plus
  // `displacement` (mm); the node's own forces no longer move those axes.
  void fixNode(int32_t node, const Vec3& displacement = Vec3::Zero(), unsigned axes = 7);
  bool isFixed(int32_t node, int axis) const;

  // External force on a node (mN) for the next steps, until changed or cleared.
  void setExternalForce(int32_t node, const Vec3& force_mN);
  void clearExternalForces();
  // Viscous damping on one node (kg/s, that is mN s/mm or N s/m) on top of
  // the mass-proportional damping, for the next steps until changed; 0
  // removes it. Central in velocity like the mass-proportional damping, so
  // stable at any value. Allocation-free.
  void setNodeDamping(int32_t node, double damping);
  size_t dampedNodes() const { return m_nodeDamping.size(); }

  // Advances one time step. Allocation-free. A model at rest (as built, or
  // after resetToRest()) with no load (no external force, no body
  // acceleration, every held axis at zero) stays at rest without computing
  // anything until a load appears.
  void step();
  uint64_t steps() const { return m_steps; }
  uint64_t restingSteps() const { return m_restingSteps; }  // of steps(): at rest, not computed
  bool resting() const { return m_resting; }  // exactly at rest, and the last step found no load

  // State, mm.
  Vec3 displacement(int32_t node) const {
    const double* u = &m_u[kNodeStride * m_internal[node]];
    return {u[0], u[1], u[2]};
  }
  Vec3 position(int32_t node) const { return m_rest[node] + displacement(node); }
  const std::vector<Vec3>& restNodes() const { return m_rest; }
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

  double mass(int32_t node) const { return m_mass[m_internal[node]]; }  // kg
  double totalMass() const;
  const TLEDElements& elements() const { return m_elements; }
  // The internal force on every node (mN) at the current displacements, or at
  // displacements `u` (tests, static solves).
  void internalForces(std::span<Vec3> forces) const;
  void internalForcesAt(std::span<const Vec3> u, std::span<Vec3> forces) const;

  // Energies, uJ: kinetic from the velocity at the half step just taken,
  // strain from the neo-Hookean energy of every element (slow: reports and tests).
  double kineticEnergy() const;
  double strainEnergy() const;

  // Running totals of the element loop.
  const ElementStepCounts& counts() const { return m_counts; }
  // Elements with J <= 0 in the last step.
  uint64_t invertedNow() const { return m_invertedNow; }

 private:
  void findCriticalStep();
  void copyToSingle();  // the element arrays, when the loop runs in single precision
  bool loaded() const;  // a force, an acceleration or a held displacement would move it from rest
  void forcesInto(const std::vector<double>& u, std::vector<double>& f) const;

  std::vector<Vec3> m_rest;                        // mesh order
  std::vector<int32_t> m_internal, m_external;     // node: mesh -> internal, internal -> mesh
  std::vector<int32_t> m_elementInternal;          // element: mesh -> internal
  TLEDElements m_elements;
  // Per internal element: mm^3, kg/mm^3 (effective, and the material's), 1 / |grad N| mm.
  std::vector<double> m_volume, m_density, m_materialDensity, m_length;
  std::vector<double> m_mass;                         // kg, lumped, per internal node
  // kNodeStride doubles per internal node:
  std::vector<double> m_u, m_uPrev;  // mm, now and one step ago
  mutable std::vector<double> m_f;   // mN, the step's internal less external forces
  ElementLoopIsa m_isa = bestElementLoopIsa();
  std::vector<double> m_stepScale;   // dt^2 / (m (1 + a dt / 2)) per internal node, mm / mN
  struct HeldAxis {
    size_t index;  // into the node vectors
    double value;  // mm
  };
  std::vector<HeldAxis> m_held;  // held axes, and every axis of a node without mass
  struct ExternalForce {
    int32_t node;  // internal
    Vec3 force;    // mN
  };
  std::vector<ExternalForce> m_externalForces;  // reserved for every node
  std::vector<int32_t> m_externalSlot;          // per internal node: its entry, or -1
  struct NodeDamping {
    int32_t node;            // internal
    double damping;          // kg/s
    double before[kNodeStride];  // mm, u- during a step
  };
  std::vector<NodeDamping> m_nodeDamping;  // reserved for every node
  std::vector<int32_t> m_dampingSlot;      // per internal node: its entry, or -1
  double m_dt = 0, m_damping = 0;
  Vec3 m_bodyAcceleration = Vec3::Zero();
  double m_criticalStep = 0;
  size_t m_criticalElement = 0;
  uint64_t m_steps = 0, m_invertedNow = 0, m_restingSteps = 0;
  bool m_resting = true;  // exactly at rest: u = u- = 0
  ElementStepCounts m_counts;
};

}  // namespace trephine::fem
