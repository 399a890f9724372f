#include "plugins/haptics/GodObjectProxy.h"

#include "framework/core/Lifecycle.h"
#include "framework/geometry/ShellSampling.h"

namespace trephine::haptics {

void GodObjectProxy::init(InitContext& context) {
  m_tool = &*l_tool;
  m_target = &*l_target;
  m_contactMemory = m_target->reserveShell(m_tool->shellPoints());
  m_target->describeTool(m_tool->shellPoints(), m_tool->solid());
  if (l_toolChange) {
    if (!l_nextTool && !l_nextTarget)
      context.error(l_toolChange, "a tool change needs nextTool, nextTarget or both (what changes)");
    ShellTool& nextTool = l_nextTool ? *l_nextTool : *l_tool;
    ShellContactTarget& nextTarget = l_nextTarget ? *l_nextTarget : *l_target;
    m_nextContactMemory = nextTarget.reserveShell(nextTool.shellPoints());
    nextTarget.describeTool(nextTool.shellPoints(), nextTool.solid());
    if (&nextTool.device() != &l_tool->device())
      context.error(l_nextTool, "the next tool must follow the same device as the first (" +
                                    l_tool->device().path() + ")");
  } else {
    if (l_nextTool) context.error(l_nextTool, "has no effect without a toolChange");
    if (l_nextTarget) context.error(l_nextTarget, "has no effect without a toolChange");
  }
  checkTissueAction(context, *m_tool, *m_target, l_tool);
  if (l_toolChange && (l_nextTool || l_nextTarget))
    checkTissueAction(context, l_nextTool ? *l_nextTool : *l_tool, l_nextTarget ? *l_nextTarget : *l_target,
                      l_nextTool ? static_cast<const BaseField&>(l_nextTool) : l_tool);
  m_shellSag = shellSag(m_tool->shellPoints(), m_tool->leadingRadius());
  if (l_nextTool) m_nextShellSag = shellSag(l_nextTool->shellPoints(), l_nextTool->leadingRadius());
  else m_nextShellSag = m_shellSag;
  m_memory.restart(m_target->shapeFailures());
  m_settings.sweeps = !d_sweep.is("none");
  m_settings.probe = d_sweep.is("cylinder")  ? SweepProbe::Cylinder
                     : d_sweep.is("spheres") ? SweepProbe::Spheres
                                             : SweepProbe::Line;
  m_settings.rectify = d_rectify.value();
  m_settings.godObject = d_godObject.value();
}

void GodObjectProxy::checkTissueAction(InitContext& context, const ShellTool& tool, const ShellContactTarget& target,
                                       const BaseField& at) {
  // A tool that removes or coagulates tissue acts only on a target that is
  // resected; on any other it would touch and do nothing, silently.
  const TissueAction action = tool.tissueAction();
  if (action.kind == TissueAction::Kind::kNone) return;
  if (!target.resects())
    context.error(at, "this tool removes or coagulates tissue, but its target cannot be resected: aim it at a "
                      "TetraBrain with a <Resection mesh=\"@BRAIN\"/> placed before this component (after the "
                      "brain's Tissue components)");
  if (action.pedal > 0 && d_drillButton.value() > 0)
    context.error(d_drillButton, "the tool has a pedal of its own (button " + std::to_string(action.pedal) +
                                     "): set one of the two");
}

void GodObjectProxy::joinContactFrame(ContactFrame& frame) {
  for (ShellContactTarget* target : targets()) frame.queries(*target);
}

std::vector<ShellContactTarget*> GodObjectProxy::targets() const {
  std::vector<ShellContactTarget*> targets = {&*l_target};
  if (l_toolChange && l_nextTarget && &*l_nextTarget != &*l_target) targets.push_back(&*l_nextTarget);
  return targets;
}

ContactResponse GodObjectProxy::response(const Vec3& forceOnTool_N, double t) {
  ContactResponse response;
  response.t = t;
  response.memory = m_changedTools ? &m_nextContactMemory : &m_contactMemory;
  const ProxyState& state = m_memory.state;
  if (state.contact) {
    response.forceOnTarget_N = -forceOnTool_N;
    response.sites = m_frame.contact.sites;
    // The load, in every contact frame: a target that resects counts the
    // time tools touch critical tissue whether their action runs or not.
    CuttingLoad& load = response.load;
    load.center_W = state.proxy;
    load.radius = m_tool->leadingRadius();
    load.overlap = state.overlap;
    load.force_N = -forceOnTool_N;
    load.dt = 1.0 / d_rate.value();
    load.t = t;
    load.burr = m_tool->cuttingBurr();
    load.action = m_tool->tissueAction();
    response.touched = m_frame.contact.touched;
    if (state.cutting) {
      response.cutting = true;
      response.stoppedAt = m_frame.stoppedAt;
    }
  }
  return response;
}

void GodObjectProxy::changeTools(const TickContext& context) {
  // The proxy starts again where the device is, with no plane and no history
  // of the old contact; the first target hears no more responses from it
  // (the contact frame hands it none: its contact ended).
  (void)context;
  if (l_nextTool) m_tool = &*l_nextTool;
  if (l_nextTarget) m_target = &*l_nextTarget;
  m_memory.restart(m_target->shapeFailures());
  m_changedTools = true;
}

void GodObjectProxy::tick(const TickContext& context) {
  if (l_toolChange && !m_changedTools && l_toolChange->changed()) changeTools(context);
  ProxyInput input;
  // The target's frame, begun once for every tool of the frame (outside a
  // scheduler's step, nothing else shares it: begun here).
  input.frame = context.contacts ? context.contacts->frameOf(*m_target) : m_target->beginFrame(context.t);
  input.contactMemory = m_changedTools ? &m_nextContactMemory : &m_contactMemory;
  const DeviceState& device = m_tool->device().state();
  input.deviceValid = device.valid;
  if (device.valid) {
    input.toolPose = m_tool->toolPose(device.pose);
    m_orientation = input.toolPose.orientation;
  }
  // The drill, or the tool's action on tissue, runs while its pedal is held
  // (the tool's own pedal, else drillButton), or always without one.
  const int pedal = m_tool->tissueAction().pedal > 0 ? m_tool->tissueAction().pedal : d_drillButton.value();
  input.cutting = pedal == 0 || (device.buttons >> (pedal - 1)) & 1u;
  input.shell = m_tool->shellPoints();
  input.leadingRadius = m_tool->leadingRadius();
  input.shellSag = m_changedTools ? m_nextShellSag : m_shellSag;
  m_frame = stepProxy(m_settings, m_memory, input, *m_target);
  if (m_frame.startedInside && context.events)
    context.events->log(context.t, "tool_starts_inside",
                        "the tool's first pose is inside its target: the force renders the whole depth at once", this,
                        m_frame.state.rawPenetration);
  if (m_frame.letGo && context.events)
    context.events->log(context.t, "haptic_released", "the target's shape failed: proxy released to the device",
                        this);
}

std::vector<const ShellTool*> GodObjectProxy::tools() const {
  std::vector<const ShellTool*> tools = {&*l_tool};
  if (l_nextTool && &*l_nextTool != &*l_tool) tools.push_back(&*l_nextTool);
  return tools;
}

void GodObjectProxy::reportCounters(std::vector<Counter>& counters) const {
  const ProxyCounters& c = m_memory.counters;
  counters.push_back({"contact_frames", double(c.contactFrames)});
  counters.push_back({"blocked_sweeps", double(c.blockedSweeps)});
  counters.push_back({"conflict_frames", double(c.conflictFrames)});
  counters.push_back({"degenerate_normals", double(c.degenerateNormals)});
  counters.push_back({"crease_frames", double(c.creaseFrames)});
  counters.push_back({"released_holds", double(c.releasedHolds)});
  counters.push_back({"releases", double(c.releases)});
  counters.push_back({"held_anchor_frames", double(c.heldAnchors)});
  counters.push_back({"faded_release_frames", double(c.fadedReleases)});
  counters.push_back({"settled_frames", double(c.settledFrames)});
  counters.push_back({"shell_sag_mm", m_shellSag});
  counters.push_back({"starts_inside", double(c.startsInside)});
  counters.push_back({"held_outside_frames", double(c.heldOutside)});
  if (c.nonFiniteFrames) counters.push_back({"non_finite_frames", double(c.nonFiniteFrames)});
}

}  // namespace trephine::haptics
