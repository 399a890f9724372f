#include "plugins/fem/TLEDForceField.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "framework/core/Lifecycle.h"
#include "framework/core/Strings.h"
#include "plugins/fem/MaterialPlausibility.h"

namespace trephine::fem {

namespace {
constexpr double kNewtonsToModelForce = 1000.0;  // N -> mN (kg mm / s^2)
// N s/mm: above this a contactDamping is taken for a slip of units (warned).
constexpr double kMostPlausibleContactDamping = 0.1;
// Mass scaling beyond this fraction of the mesh's own mass is warned of (a few percent changes little).
constexpr double kAddedMassWarned = 0.05;

// A fraction as a percentage of four significant digits ("2.325%").
std::string percent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g%%", 100 * fraction);
  return text;
}

std::string seconds(double s) {
  std::ostringstream out;
  out.precision(3);
  out << s * 1e3 << " ms";
  return out.str();
}
}  // namespace

void TLEDForceField::init(InitContext& context) {
  DeformableMesh& brain = *l_mesh;
  const TetMesh& mesh = brain.mesh();
  const ElementMaterial material = this->material();
  try {
    m_model = std::make_unique<TLEDModel>(mesh.nodes, mesh.tets, std::span(&material, 1));
  } catch (const std::invalid_argument& e) {
    context.error(l_mesh, std::string("cannot build the FEM model of this mesh: ") + e.what());
    return;
  }
  m_labels = mesh.labels;
  // k T of a haptic spring is of the order of 0.001 N s/mm (3 N/mm acting
  // 2 ms late: 0.006): a hundred times that is a value in N s/m.
  if (d_contactDamping.value() > kMostPlausibleContactDamping)
    context.warning(d_contactDamping, "is in N s/mm; a spring k acting T late needs about k T (0.3 N/mm, 1.5 ms: "
                                      "0.00045), so " + formatDouble(d_contactDamping.value()) +
                                          " is a damping in N s/m, or far more than the contact needs");
  if (auto why = implausibleDensity(d_density.value())) context.warning(d_density, *why);
  if (auto why = implausibleYoungModulus(d_youngModulus.value())) context.warning(d_youngModulus, *why);
  m_model->setElementPrecision(d_precision.is("single") ? ElementPrecision::kSingle : ElementPrecision::kDouble);
  scaleMass();
  if (auto error = checkTimeStep()) context.error(d_dt, *error);
  if (d_massScaling.value()) {
    // The added mass slows the mesh's dynamics: said at every load, warned of
    // beyond a few percent, refused beyond maxAddedMass.
    const std::string added = "massScaling added " + percent(addedMassFraction()) +
                              " of the mesh's mass to " + std::to_string(m_massScaledElements) + " of its " +
                              std::to_string(m_model->elementCount()) + " elements";
    if (auto problem = addedMassProblem())
      context.error(d_massScaling, *problem);
    else if (addedMassFraction() > kAddedMassWarned)
      context.warning(d_massScaling, added + ": the tissue responds more slowly than its material says (a smaller "
                                             "dt, or a mesh without its smallest or flattest elements, adds less)");
    else
      context.note(d_massScaling, added);
  }

  // Tetrahedra a resection removes (none unless the brain is resected).
  m_removals = &brain.subscribeRemovals();
  m_channel = &context.channels().publish<NodePositions>(*this, kNodePositionsChannel);
  m_stressChannel = &context.channels().publish<ElementStress>(*this, kElementStressChannel);
  if (auto error = brain.followDeformation(*this, context.channels())) {
    context.error(l_mesh, *error);
    return;
  }
  m_frame.positions = mesh.nodes;
  m_frame.allMoved = true;
  // The size of the body: the nodes its elements hold. A node no element
  // holds (a stray vertex left in a file) does not move and is not part of
  // it; counted, one at 1 m would make the divergence bound below a metre
  // for a 20 mm brain, and shapes torn apart by a diverging step would
  // reach the collision as if they were valid.
  Box3 box;
  for (const TetIndices& tet : mesh.tets)
    for (int32_t node : tet) box.extend(mesh.nodes[node]);
  m_meshSize = box.diagonal().norm();
  m_channel->reserve(m_frame);  // slots as large as a frame: publishing never allocates
  m_forces = context.channels().subscribe<NodeForces>(*l_mesh.boundComponent(), kNodeForcesChannel);
}

void TLEDForceField::scaleMass() {
  if (!d_massScaling.value()) return;
  // Damping lowers the stable step by about a factor 1 - damping dt / 4: aim a little above dt.
  m_massScaledElements =
      m_model->scaleMassForStep(d_stepMargin.value() * d_dt.value() * (1 + d_damping.value() * d_dt.value()));
}

double TLEDForceField::addedMassFraction() const {
  const double own = m_model->totalMass() - m_model->addedMass();
  return own > 0 ? m_model->addedMass() / own : 0.0;
}

std::optional<std::string> TLEDForceField::addedMassProblem() const {
  if (!d_massScaling.value() || addedMassFraction() <= d_maxAddedMass.value()) return std::nullopt;
  return "massScaling would add " + percent(addedMassFraction()) + " of the mesh's mass (to " +
         std::to_string(m_massScaledElements) + " of its " + std::to_string(m_model->elementCount()) +
         " elements), more than maxAddedMass = " + percent(d_maxAddedMass.value()) +
         ": the dynamics would be another material's. Use a smaller dt (the critical step of this mesh is " +
         seconds(m_model->unscaledCriticalTimeStep()) +
         "), a mesh without its smallest or flattest elements (or at the right scale: a mesh in metres read as mm "
         "needs a million times the mass), or raise maxAddedMass to accept it";
}

std::optional<std::string> TLEDForceField::checkTimeStep() const {
  const double critical = m_model->criticalTimeStep(d_damping.value());
  if (d_dt.value() <= critical || d_acceptUnstable.value()) return std::nullopt;
  const std::string problem =
      "dt = " + seconds(d_dt.value()) + " is above the critical time step of this mesh, " + seconds(critical) +
      " (element " + std::to_string(m_model->criticalElement()) +
      ": its characteristic length over the dilatational wave speed, with the damping): the explicit integration "
      "would diverge. ";
  const size_t below = m_model->elementsBelowStep(d_dt.value());
  if (d_massScaling.value())  // already on: more mass is not what is missing
    return problem + "massScaling is on already" +
           (below == 0 ? std::string(" and every element's own step reaches dt: the damping limits it")
                       : ", and " + std::to_string(below) + " elements stay below dt") +
           ". Use dt <= " + seconds(critical) + ", less damping, or acceptUnstableTimeStep=\"true\"";
  return problem + "Use dt <= " + seconds(critical) + ", or massScaling=\"true\" (" + std::to_string(below) +
         " elements are below dt), or acceptUnstableTimeStep=\"true\"";
}

std::optional<std::string> TLEDForceField::assignLabelMaterial(int label, const ElementMaterial& material) {
  if (m_labels.empty()) return "the mesh " + brainPath() + " carries no tissue labels";
  std::vector<int32_t> elements;
  for (size_t e = 0; e < m_labels.size(); ++e)
    if (m_labels[e] == label) elements.push_back(int32_t(e));
  if (elements.empty()) return "no element of " + brainPath() + " has label " + std::to_string(label);
  m_model->assignMaterial(elements, material);
  scaleMass();
  if (auto problem = addedMassProblem()) return problem;
  return checkTimeStep();
}

void TLEDForceField::prepare(const RunPlan&) {
  m_model->setTimeStep(d_dt.value(), d_damping.value());
  // After every component's init: the constraints and gravity are in the model.
  m_state.emplace(*m_model);
  const size_t n = m_model->nodeCount();
  m_target.assign(n, Vec3::Zero());
  m_applied.assign(n, Vec3::Zero());
  m_applying.assign(n, 0);
  m_targetNodes.reserve(n);
  m_appliedNodes.reserve(n);
  m_removedBatch.clear();
  m_removedBatch.reserve(m_model->elementCount());
  // Stresses only for a reader (every reader subscribed at init).
  m_stress = {};
  if (m_stressChannel->readerCount() > 0) {
    m_stress.vonMises.assign(m_model->elementCount(), 0.0f);
    m_stressChannel->reserve(m_stress);
  }
  m_lastStress = -INFINITY;
  m_stressAtRest = false;
  m_stressUpdates = 0;
  m_stressCursor = 0;
}

void TLEDForceField::publishStress(double t, double period) {
  if (m_stress.vonMises.empty()) return;
  const bool resting = m_state->resting();
  if (m_stressCursor == 0) {
    // A sweep starts when one is due, and not for a shape at rest already published.
    if (t - m_lastStress < d_stressInterval.value() || (resting && m_stressAtRest)) return;
    m_lastStress = t;
    m_sweepResting = true;
  }
  // A share of the elements each tick, so that a sweep takes about one
  // interval and no tick pays for the whole mesh (about 60 ns an element).
  const size_t elements = m_stress.vonMises.size();
  const size_t ticks = std::max<size_t>(1, size_t(d_stressInterval.value() / period));
  const size_t slice = (elements + ticks - 1) / ticks;
  m_state->vonMisesStress(m_stress.vonMises, m_stressCursor, slice);
  m_stressCursor += slice;
  m_sweepResting = m_sweepResting && resting;
  if (m_stressCursor < elements) return;
  m_stressCursor = 0;
  m_stress.t = t;
  m_stressChannel->publish(m_stress);
  m_stressAtRest = m_sweepResting;
  ++m_stressUpdates;
}

void TLEDForceField::tick(const TickContext& context) {
  ++m_ticks;
  // Elements a resection removed since the last tick leave the model before
  // this step (their forces and their mass share; nodes left without an
  // element are held): the model follows within the frame, without a rebuild.
  if (m_removals) {
    m_removedBatch.clear();
    m_removals->drain([&](int32_t tet) {
      if (m_removedBatch.size() < m_removedBatch.capacity()) m_removedBatch.push_back(tet);
    });
    if (!m_removedBatch.empty()) m_removedElements += m_model->removeElements(m_removedBatch);
  }
  // Forces measured on a shape from before the last reset belong to a contact
  // that is gone (the haptic side lets go when it sees the reset): dropped.
  if (m_forces->fetch() && m_forces->read().resetsSeen == m_frame.resets) {
    // The tool's latest reaction replaces the previous one as the target.
    for (int32_t node : m_targetNodes) m_target[node] = Vec3::Zero();
    m_targetNodes.clear();
    const NodeForces& latest = m_forces->read();
    for (const NodeForce& f : latest.forces) {
      if (f.node < 0 || size_t(f.node) >= m_model->nodeCount() || !f.force.allFinite()) {
        ++m_droppedForces;
        continue;
      }
      m_target[f.node] = kNewtonsToModelForce * f.force;
      if (m_targetNodes.size() < m_targetNodes.capacity()) m_targetNodes.push_back(f.node);
      if (!m_applying[f.node]) {
        m_applying[f.node] = 1;
        m_appliedNodes.push_back(f.node);  // capacity: every node
      }
    }
    ++m_forceUpdates;
  }
  // The applied force follows the target with the time constant forceSmoothing
  // (at once when 0); a node whose force has died away leaves the list.
  const double follow = d_forceSmoothing.value() > 0 ? 1 - std::exp(-context.dt / d_forceSmoothing.value()) : 1.0;
  size_t kept = 0;
  double total = 0;  // mN, of the applied forces' magnitudes
  for (int32_t node : m_appliedNodes) {
    m_applied[node] += follow * (m_target[node] - m_applied[node]);
    const bool done = m_target[node].isZero(0.0) && m_applied[node].norm() < 1e-9;  // mN
    if (done) m_applied[node] = Vec3::Zero();
    m_state->setExternalForce(node, m_applied[node]);
    total += m_applied[node].norm();
    if (done) {
      m_applying[node] = 0;
      m_state->setNodeDamping(node, 0);
    } else {
      m_appliedNodes[kept++] = node;
    }
  }
  m_appliedNodes.resize(kept);
  // contactDamping, shared as the force is: N s/mm, in the model's kg/s
  // (N s/m, the mN of a mm/s) times 1000.
  if (d_contactDamping.value() > 0)
    for (int32_t node : m_appliedNodes)
      m_state->setNodeDamping(node, total > 0 ? kNewtonsToModelForce * d_contactDamping.value() * m_applied[node].norm() / total
                                              : 0.0);
  // As many steps as fit: the model's time stays within one step of the end
  // of this period. In real time, after a stall (a tick that came late), at
  // most one step more than a period holds: the model falls behind the clock
  // (counted) rather than take ever longer ticks to catch up.
  const double dt = m_model->timeStep();
  uint64_t target = uint64_t(std::floor((context.t + context.dt) / dt + 1e-9)) - m_droppedSteps;
  const uint64_t most = uint64_t(std::ceil(context.dt / dt - 1e-9)) + 1;
  if (target > m_state->steps() + most) {
    m_droppedSteps += target - (m_state->steps() + most);
    target = m_state->steps() + most;
  }
  uint64_t substeps = 0;
  while (m_state->steps() < target) {
    m_state->step();
    m_mostInverted = std::max(m_mostInverted, m_state->invertedNow());
    ++substeps;
  }
  m_mostSubsteps = std::max(m_mostSubsteps, substeps);
  // At rest and published so: the brain already has this shape (the rest
  // shape before the first frame).
  if (m_state->resting() && m_publishedRest) return publishStress(context.t + context.dt, context.dt);
  const TLEDState::WrittenShape shape = m_state->writePositions(m_frame.positions);
  const double largest = shape.largestDisplacement;
  // A node farther from rest than the mesh is large has diverged as surely
  // as a NaN (and would widen every collision query by as much).
  if (!(largest <= m_meshSize)) {
    // Diverged: an accepted unstable step, or a load the mesh cannot carry (a
    // point force that pushes a node past its neighbours inverts elements,
    // and explicit steps blow up there). The collision keeps the last finite
    // shape; the model starts again from rest, and the event says when.
    ++m_nonFinite;
    ++m_frame.resets;  // carried by the rest shape published next: the haptic side lets go
    if (context.events) context.events->log(context.t, "fem_diverged", "reset to rest", this);
    m_state->resetToRest();
    dropToolLoad();
    m_movesKnown = false;  // the shape held is not the one last published
    m_publishedRest = false;
    return;
  }
  m_largestDisplacement = std::max(m_largestDisplacement, largest);
  m_frame.displacementBound = largest;
  m_frame.largestMove = m_movesKnown ? shape.largestMove : INFINITY;
  m_movesKnown = true;
  ++m_frame.step;
  m_channel->publish(m_frame);
  m_publishedRest = m_state->resting();
  publishStress(context.t + context.dt, context.dt);  // of a shape that did not diverge
}

void TLEDForceField::dropToolLoad() {
  // The load the mesh could not carry goes with the shape it tore: applied
  // again at once, it would tear the rest shape within a tick, again and
  // again, before the haptic side ever saw the reset.
  for (int32_t node : m_targetNodes) m_target[node] = Vec3::Zero();
  m_targetNodes.clear();
  for (int32_t node : m_appliedNodes) {
    m_applied[node] = Vec3::Zero();
    m_applying[node] = 0;
    m_state->setExternalForce(node, Vec3::Zero());
    m_state->setNodeDamping(node, 0);
  }
  m_appliedNodes.clear();
}

void TLEDForceField::reportCounters(std::vector<Counter>& counters) const {
  if (!m_model) return;
  counters.push_back({"elements", double(m_model->elementCount())});
  if (m_removedElements) counters.push_back({"removed_elements", double(m_removedElements)});
  counters.push_back({"critical_dt_s", m_model->criticalTimeStep(d_damping.value())});
  if (d_massScaling.value()) {
    counters.push_back({"mass_scaled_elements", double(m_massScaledElements)});
    counters.push_back({"added_mass_fraction", m_model->addedMass() / (m_model->totalMass() - m_model->addedMass())});
  }
  if (!m_state) return;  // not run
  counters.push_back({"steps", double(m_state->steps())});
  counters.push_back({"most_substeps", double(m_mostSubsteps)});
  counters.push_back({"dropped_steps", double(m_droppedSteps)});  // behind the clock after stalls (real time)
  counters.push_back({"inverted_element_steps", double(m_state->counts().inverted)});
  counters.push_back({"most_inverted_elements", double(m_mostInverted)});
  counters.push_back({"far_from_rest_element_steps", double(m_state->counts().farFromRest)});
  counters.push_back({"largest_displacement_mm", m_largestDisplacement});
  counters.push_back({"force_updates", double(m_forceUpdates)});
  counters.push_back({"dropped_forces", double(m_droppedForces)});
  counters.push_back({"non_finite_ticks", double(m_nonFinite)});
  counters.push_back({"published_steps", double(m_frame.step)});
  counters.push_back({"stress_updates", double(m_stressUpdates)});  // only while a component reads them
  counters.push_back({"resting_steps", double(m_state->restingSteps())});  // at rest, no load: not computed
}

}  // namespace trephine::fem
