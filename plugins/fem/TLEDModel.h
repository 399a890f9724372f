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
//
// The model is what stays fixed while it moves (MuJoCo's mjModel): the rest
// shape, the element matrices, the masses, the time step, gravity and the
// held axes. What moves is a TLEDState (TLEDState.h, MuJoCo's mjData): the
// displacements, the loads on the nodes and the step counts. One model
// serves any number of states; a copy of a state replays its steps exactly.
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

class TLEDState;

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
  // The critical time step (s, undamped) of the materials' own densities,
  // as it was before any mass scaling.
  double unscaledCriticalTimeStep() const;

  // Takes `elements` (the mesh's indices) out of the model, as resection
  // removes them: their forces leave the element loop (their moduli become
  // 0; the loop's arrays keep their shape) and their share of the lumped
  // masses leaves their nodes; a node left with no element belongs to
  // nothing and is held at its rest position. Indices out of range or
  // already removed are skipped; returns how many went. Does not allocate:
  // the FEM's thread calls it between steps. Every state of the model
  // follows at its next step.
  size_t removeElements(std::span<const int32_t> elements);
  bool removed(int32_t element) const { return m_elementRemoved[size_t(m_elementInternal[size_t(element)])] != 0; }
  size_t removedCount() const { return m_removedCount; }

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
  const Vec3& bodyAcceleration() const { return m_bodyAcceleration; }
  // Holds `axes` (bit 0: x, 1: y, 2: z) of a node at its rest position plus
  // `displacement` (mm); the node's own forces no longer move those axes.
  // The value may change between steps (a prescribed displacement): every
  // state of the model takes it, now and one step ago, at its next step.
  void fixNode(int32_t node, const Vec3& displacement = Vec3::Zero(), unsigned axes = 7);
  bool isFixed(int32_t node, int axis) const;

  const std::vector<Vec3>& restNodes() const { return m_rest; }
  double mass(int32_t node) const { return m_mass[m_internal[node]]; }  // kg
  double totalMass() const;
  const TLEDElements& elements() const { return m_elements; }
  // The internal force on every node (mN) at displacements `u` (mm; tests,
  // static solves). Allocates.
  void internalForcesAt(std::span<const Vec3> u, std::span<Vec3> forces) const;

 private:
  friend class TLEDState;  // steps on the arrays below, in the model's internal order

  void findCriticalStep();
  void copyToSingle();  // the element arrays, when the loop runs in single precision
  // kNodeStride doubles per internal node: the internal forces at `u` into `f` (mN).
  ElementStepCounts forcesInto(const double* u, double* f) const;
  size_t vectorSize() const { return kNodeStride * m_rest.size(); }
  size_t index(int32_t node, size_t axis) const { return kNodeStride * size_t(m_internal[node]) + axis; }

  std::vector<Vec3> m_rest;                        // mesh order
  std::vector<int32_t> m_internal, m_external;     // node: mesh -> internal, internal -> mesh
  std::vector<int32_t> m_elementInternal;          // element: mesh -> internal
  std::vector<int32_t> m_elementExternal;          // element: internal -> mesh
  TLEDElements m_elements;
  // Per internal element: mm^3, kg/mm^3 (effective, and the material's), 1 / |grad N| mm.
  std::vector<double> m_volume, m_density, m_materialDensity, m_length;
  std::vector<double> m_mass;                         // kg, lumped, per internal node
  std::vector<uint8_t> m_elementRemoved;              // per internal element: taken out (removeElements)
  std::vector<uint32_t> m_nodeElements;               // per internal node: elements of the model using it
  size_t m_removedCount = 0;
  ElementLoopIsa m_isa = bestElementLoopIsa();
  std::vector<double> m_stepScale;   // dt^2 / (m (1 + a dt / 2)) per internal node, mm / mN
  struct HeldAxis {
    size_t index;  // into the node vectors
    double value;  // mm
  };
  std::vector<HeldAxis> m_held;  // held axes, and every axis of a node without mass
  double m_dt = 0, m_damping = 0;
  Vec3 m_bodyAcceleration = Vec3::Zero();
  double m_criticalStep = 0;
  size_t m_criticalElement = 0;
};

}  // namespace trephine::fem
