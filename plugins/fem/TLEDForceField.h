#pragma once
// The brain's mechanics: TLED on the linear tetrahedra of a TetraBrain
// (TLEDModel, moving a TLEDState), ticked in its own rate group. Each tick it takes the latest
// reaction forces of the tool on the nodes (the brain's node_forces, N),
// advances as many time steps as fit in the period, and publishes the node
// positions on node_positions, which the brain reads at the start of each
// haptic frame. Constraints (FixedConstraint), body forces (Gravity) and
// per-tissue materials (LabelMaterial) are components of their own that link
// here: a scene without them has none.
//
// Units: the scene's (mm, kg, s), as the thesis's Table 6.1: density kg/mm^3,
// Young's modulus kPa, forces on the model mN. The tool's forces arrive in N
// and are multiplied by 1000 at the channel.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/core/ChannelHub.h"
#include "framework/core/Component.h"
#include "framework/geometry/DeformableMesh.h"
#include "plugins/fem/TLEDModel.h"
#include "plugins/fem/TLEDState.h"

namespace trephine::fem {

class TLEDForceField final : public Component {
 public:
  static constexpr std::string_view kTypeName = "TLEDForceField";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void tick(const TickContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  // For the components that link here, during their init() (after this one's).
  TLEDModel& model() { return *m_model; }
  const DeformableMesh& brain() const { return *l_mesh; }
  // The deformed mesh's path, for messages.
  std::string brainPath() const { return l_mesh.boundComponent()->path(); }
  bool hasModel() const { return m_model != nullptr; }
  // Gives the elements of tissue `label` their own material; returns why it
  // cannot (no element has the label, the time step is no longer stable).
  std::optional<std::string> assignLabelMaterial(int label, const ElementMaterial& material);
  double timeStep() const { return d_dt.value(); }
  // The FEM's own material (fields density, youngModulus, poissonRatio).
  ElementMaterial material() const { return {d_density.value(), d_youngModulus.value(), d_poissonRatio.value()}; }

 private:
  // Why dt is above the stable step, or nothing (or accepted).
  std::optional<std::string> checkTimeStep() const;
  // With massScaling, scales the elements whose step is below dt (again after a material change).
  void scaleMass();
  // The mass scaling added (a fraction of the mesh's own mass), and why it is
  // refused when above maxAddedMass.
  double addedMassFraction() const;
  std::optional<std::string> addedMassProblem() const;

  // Followed at init only: the ticks exchange positions and forces with the
  // brain through channels, so the FEM may run in a rate group of its own.
  Link<DeformableMesh> l_mesh{
      this, "mesh", {.help = "The tetrahedral mesh this deforms", .required = true, .initOnly = true}};
  Field<double> d_density{this,
                          "density",
                          1e-6,
                          {.help = "Mass density (Table 6.1: 1e-6, water's)",
                           .unit = "kg/mm^3",
                           .min = 0.0,
                           .minExclusive = true}};
  Field<double> d_youngModulus{this,
                               "youngModulus",
                               30.0,
                               {.help = "Young's modulus of the neo-Hookean material (Table 6.1: 30)",
                                .unit = "kPa",
                                .min = 0.0,
                                .minExclusive = true}};
  Field<double> d_poissonRatio{
      this,
      "poissonRatio",
      0.3,
      {.help = "Poisson's ratio (Table 6.1: 0.3); below 0.5, and the closer to it the smaller the stable time step",
       .min = -0.99,
       .max = 0.499}};
  Field<double> d_damping{this,
                          "damping",
                          50.0,
                          {.help = "Mass-proportional damping coefficient: each node feels -damping m v",
                           .unit = "1/s",
                           .min = 0.0}};
  Field<double> d_dt{this,
                     "dt",
                     0.33e-3,
                     {.help = "Time step of the central differences (the thesis's 0.33 ms); the FEM takes as many "
                              "steps per tick as fit in its period. Above the critical step of the mesh it is a load "
                              "error unless acceptUnstableTimeStep is set",
                      .unit = "s",
                      .min = 0.0,
                      .minExclusive = true}};
  Field<bool> d_acceptUnstable{this,
                               "acceptUnstableTimeStep",
                               false,
                               {.help = "Run with a dt above the critical time step of the mesh (the simulation will "
                                        "diverge: for tests of what follows)"}};
  Field<double> d_forceSmoothing{
      this,
      "forceSmoothing",
      0.005,
      {.help = "Time constant with which the tool's force on the nodes follows the latest from the haptic loop "
               "(0: at once). The haptic spring and a soft brain answer each other a frame late; where the brain's "
               "local stiffness is near the spring's, they chatter at half the frame rate, and a few milliseconds "
               "of smoothing stops it (the default, which every shipped scene uses)",
       .unit = "s",
       .min = 0.0}};
  Field<double> d_contactDamping{
      this,
      "contactDamping",
      0.002,
      {.help = "Viscous damping of the brain where the tool presses, shared among the pressed nodes as the force "
               "is. The haptic spring acts on the brain a frame or two late, and a spring k acting T late feeds "
               "the surface like a negative damping of about k T; this returns it (0.3 N/mm and 1.5 ms: 0.00045; "
               "the default, 0.002, is what every shipped scene uses)",
       .unit = "N s/mm",
       .min = 0.0}};
  EnumField d_precision{this,
                        "precision",
                        {"double", "single"},
                        "double",
                        {.help = "Arithmetic of the element loop: single runs about 1.2 to 1.3 times as fast here "
                                 "(docs/results.md) with stresses to about 1e-7 of the moduli (strains below about "
                                 "1e-6 are lost in rounding); positions and velocities stay in double"}};
  Field<bool> d_massScaling{
      this,
      "massScaling",
      false,
      {.help = "Selective mass scaling: the elements whose own critical time step is below dt get the density that "
               "makes it dt (the rest keep theirs), so that dt is stable on a mesh with a few small or flat "
               "elements. The added mass is reported (added_mass_fraction)"}};
  Field<double> d_stepMargin{
      this,
      "stepMargin",
      1.0,
      {.help = "With massScaling: the critical time step the scaled elements reach, as a multiple of dt. At 1 they "
               "are stable at rest only: an element squeezed under a tool stiffens, its step falls below dt and "
               "the integration diverges within a few steps. 1.5 to 2 leaves room for the compression a small "
               "tissue's elements see under a tool (resection)",
       .min = 1.0,
       .max = 10.0}};
  Field<double> d_maxAddedMass{
      this,
      "maxAddedMass",
      0.25,
      {.help = "Most mass that massScaling may add, as a fraction of the mesh's own: beyond it the load is refused "
               "(the dynamics would no longer be the tissue's: a smaller dt, or a mesh without its smallest or "
               "flattest elements, is the fix; raise this to accept it). Above 0.05 the load warns",
       .min = 0.0}};
  Field<double> d_stressInterval{
      this,
      "stressInterval",
      1.0 / 30,
      {.help = "While a component reads the elements' stresses (element_stress: a VtkExporter colouring the brain "
               "by von Mises stress), they are computed at most this often, a share of the elements each tick so "
               "that no tick pays for the whole mesh (a sweep's elements are of shapes up to this far apart); with "
               "no reader, never",
       .unit = "s",
       .min = 0.0}};
  RateField d_rate{this, 1000.0, "Rate of the FEM's group: each tick advances the model by one period"};

  // After a divergence: the tool's forces, fetched and applied, are dropped.
  void dropToolLoad();
  // While read: computes a share of the elements' stresses each tick (a
  // sweep over all of them takes about stressInterval; `period`, s, the
  // tick's) and publishes them when a sweep ends.
  void publishStress(double t, double period);

  std::unique_ptr<TLEDModel> m_model;
  std::optional<TLEDState> m_state;  // made at prepare(), once the components that link here have set the model
  std::vector<int32_t> m_labels;  // per element, the mesh's tissue labels (or empty)
  std::optional<ChannelReader<NodeForces>> m_forces;
  // The tool's forces (mN) per node: the last fetched (target) and those
  // applied, which follow it with the time constant forceSmoothing.
  std::vector<Vec3> m_target, m_applied;
  std::vector<char> m_applying;                    // 1: the node is in m_appliedNodes
  std::vector<int32_t> m_targetNodes, m_appliedNodes;
  ChangeQueue<int32_t>* m_removals = nullptr;  // the brain's removed tetrahedra (resection)
  std::vector<int32_t> m_removedBatch;          // capacity: every element
  uint64_t m_removedElements = 0;
  Channel<NodePositions>* m_channel = nullptr;
  NodePositions m_frame;
  Channel<ElementStress>* m_stressChannel = nullptr;
  ElementStress m_stress;  // sized at prepare() when read
  double m_lastStress = -INFINITY;  // s
  bool m_stressAtRest = false;  // the stress last published is the rest shape's (zero)
  uint64_t m_stressUpdates = 0;
  size_t m_stressCursor = 0;   // the next element of the sweep (the model's order); 0: none under way
  bool m_sweepResting = true;  // at rest at every tick of the sweep
  bool m_movesKnown = true;  // m_frame.positions holds the shape last published
  bool m_publishedRest = true;  // the brain's shape is the rest shape (nothing published yet, or rest)
  uint64_t m_ticks = 0, m_forceUpdates = 0, m_droppedForces = 0, m_mostSubsteps = 0, m_nonFinite = 0;
  uint64_t m_mostInverted = 0, m_droppedSteps = 0;
  size_t m_massScaledElements = 0;
  double m_largestDisplacement = 0;  // mm
  double m_meshSize = 0;             // mm, the diagonal of the box of the nodes elements hold: no node moves farther
};

}  // namespace trephine::fem
