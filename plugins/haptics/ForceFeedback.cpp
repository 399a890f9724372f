#include "plugins/haptics/ForceFeedback.h"

#include <algorithm>
#include <cmath>

#include "framework/core/Lifecycle.h"
#include "plugins/haptics/SampledDataPassivity.h"

namespace trephine::haptics {

void ForceFeedback::init(InitContext& context) {
  m_log = context.claimHapticLog(*this, d_trace.value());
  // The summary judges force steps beyond what k and b explain from the device's motion.
  // After a tool change the gains may change: the larger of each explains more, so the judge is not harsher.
  if (m_log)
    m_log->setRenderingGains(std::max(d_stiffness.value(), d_nextStiffness.value()),
                             std::max(d_damping.value(), d_nextDamping.value()));
  // The observer counts the device's own damping too, as the check below does.
  if (m_log)
    if (const std::optional<double> b = l_proxy->tool().device().physicalDamping()) m_log->setDeviceDamping(*b);
  if ((d_nextStiffness.isSet() || d_nextDamping.isSet()) && !l_proxy->hasToolChange())
    context.error(d_nextStiffness.isSet() ? static_cast<const BaseField&>(d_nextStiffness) : d_nextDamping,
                  "has no effect: the proxy " + l_proxy->path() + " has no toolChange");
  m_samples = &context.channels().publish<Sample>(*this, kSampleChannel);
  // On a device with dynamics (a simulated hand), flag a rendering that cannot be passive.
  warnIfNotPassive(context, d_stiffness, d_stiffness.value(), d_damping.value(), rateHz(), l_proxy->tool().device());
  if (d_nextStiffness.isSet() || d_nextDamping.isSet())
    warnIfNotPassive(context, d_nextStiffness.isSet() ? static_cast<const BaseField&>(d_nextStiffness) : d_nextDamping,
                     stiffnessAfterChange(), dampingAfterChange(), rateHz(), l_proxy->tool().device());
}

void ForceFeedback::joinContactFrame(ContactFrame& frame) {
  m_responder = frame.addResponder(path(), l_proxy->targets());
}

double ForceFeedback::stiffnessAfterChange() const {
  return d_nextStiffness.value() >= 0 ? d_nextStiffness.value() : d_stiffness.value();
}
double ForceFeedback::dampingAfterChange() const {
  return d_nextDamping.value() >= 0 ? d_nextDamping.value() : d_damping.value();
}
double ForceFeedback::stiffness() const {
  return l_proxy->changedTools() ? stiffnessAfterChange() : d_stiffness.value();
}
double ForceFeedback::damping() const { return l_proxy->changedTools() ? dampingAfterChange() : d_damping.value(); }

std::vector<std::string> ForceFeedback::sampleColumns() const {
  return {"device_x", "device_y", "device_z", "proxy_x",  "proxy_y",     "proxy_z",         "force_x", "force_y",
          "force_z",  "normal_x", "normal_y", "normal_z", "penetration", "penetration_raw", "points",  "primitives",
          "tool_radius", "tool_in_hand", "tool_qw", "tool_qx", "tool_qy", "tool_qz"};
}

void ForceFeedback::tick(const TickContext& context) {
  GodObjectProxy& proxy = *l_proxy;
  const ProxyState& s = proxy.state();
  HapticDevice& device = proxy.tool().device();

  if (s.released && !m_wasReleased) {
    // The proxy was let go (what shapes its target failed): the force it
    // rendered fades to zero along a ramp, a step would kick the hand.
    m_rampFrom = m_force;
    m_rampFrames = std::max<uint64_t>(1, uint64_t(std::lround(d_releaseRamp.value() * rateHz())));
    m_rampFrame = 0;
    ++m_releaseRamps;
  }
  m_wasReleased = s.released;
  Vec3 force = Vec3::Zero();
  const bool fading = m_rampFrame < m_rampFrames;
  if (fading) {
    ++m_rampFrame;
    force = (1.0 - double(m_rampFrame) / double(m_rampFrames)) * m_rampFrom;
  } else if (s.contact) {
    // The spring's share is capped at maxForce, as if the device-proxy gap were
    // at most maxForce / k: a device pushed far past the clamp stores no force
    // that pulling back would first have to undo, and the damping keeps acting
    // at the clamp (with the clamp alone it is masked there, so a saturated
    // contact loses its dissipation).
    const double k = stiffness(), b = damping();
    const double spring = std::min(k * s.penetration, d_maxForce.value());  // N
    const double normalSpeed = device.state().velocity.dot(s.normal);  // mm/s, negative when pressing in
    const double magnitude = spring - b * normalSpeed;
    if (magnitude > d_maxForce.value() || k * s.penetration > d_maxForce.value())
      ++m_saturatedFrames;
    force = std::clamp(magnitude, 0.0, d_maxForce.value()) * s.normal;  // never pulls the hand in
  }
  if (d_maxForceStep.value() > 0) {
    const Vec3 step = force - m_force;
    const double stepNorm = step.norm();
    if (stepNorm > d_maxForceStep.value()) {
      force = m_force + step * (d_maxForceStep.value() / stepNorm);
      ++m_stepLimitedFrames;
    }
  }
  if (!force.allFinite()) force = m_force;  // never send a NaN; hold the last force
  m_force = force;
  device.applyForce(force);
  // The target's response to this frame's contact: the force on it and, while
  // the drill runs, the cut (applied at the start of the next frame). Every
  // frame, so that a deformable target knows when the contact ended. A
  // fading force belongs to the contact that was let go, not to the target.
  const ContactResponse response = proxy.response(fading ? Vec3::Zero() : force, context.t);
  if (context.contacts)
    context.contacts->respond(m_responder, proxy.target(), response);
  else
    proxy.target().respond(context.t, {&response, 1});  // outside a scheduler's step: the only response of the frame

  HapticFrame frame;
  frame.t = context.t;
  frame.device = s.device;
  frame.proxy = s.proxy;
  frame.force = force;
  frame.penetration = s.contact ? s.penetration : 0.0;
  frame.normal = s.normal;
  frame.contacts = s.contact ? std::max(1, s.points) : 0;
  frame.proxyInside = s.proxyInside;
  frame.rawPenetration = s.rawPenetration;
  frame.primitives = s.primitives;
  frame.removed = s.removed;
  frame.target = &proxy.target();
  frame.tool = &proxy.tool();
  if (m_log) m_log->record(frame);

  Sample sample;
  sample.t = context.t;
  size_t k = 0;
  for (const Vec3* v : {&frame.device, &frame.proxy, &frame.force, &frame.normal})
    for (int i = 0; i < 3; ++i) sample.values[k++] = (*v)[i];
  sample.values[k++] = frame.penetration;
  sample.values[k++] = frame.rawPenetration;
  sample.values[k++] = s.points;
  sample.values[k++] = s.primitives;
  // mm: the burr of the tool in hand (it changes with a ToolChange), which
  // the viewer draws and whose surface the contact point is on; a capsule's
  // bounding radius is its shaft's length.
  sample.values[k++] = proxy.tool().leadingRadius();
  // Which of heldTools() is in hand, and its orientation: the viewer and the
  // files draw its surface (ShellTool::displaySurface) at the proxy.
  sample.values[k++] = proxy.toolIndex();
  const Quat& q = proxy.orientation();
  for (const double c : {q.w(), q.x(), q.y(), q.z()}) sample.values[k++] = c;
  m_samples->publish(sample);
}

void ForceFeedback::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"saturated_frames", double(m_saturatedFrames)});
  counters.push_back({"step_limited_frames", double(m_stepLimitedFrames)});
  counters.push_back({"release_ramps", double(m_releaseRamps)});
}

}  // namespace trephine::haptics
