#include "plugins/haptics/ContactWarning.h"

#include "framework/core/Lifecycle.h"

namespace trephine::haptics {

void ContactWarning::init(InitContext&) { l_target->reserveShell(l_proxy->tool().shellPoints()); }

void ContactWarning::tick(const TickContext& context) {
  if (l_until && l_until->changed()) return;
  const ShellTool& tool = l_proxy->tool();
  const DeviceState& device = tool.device().state();
  if (!device.valid) return;
  ShellContactTarget& target = *l_target;
  if (context.contacts)
    context.contacts->frameOf(target);
  else
    target.beginFrame(context.t);
  const Pose X_WT{l_proxy->state().proxy, tool.toolPose(device.pose).orientation};
  ++m_queries;
  const bool touching = target.overlaps(X_WT, tool.shellPoints());
  if (touching) ++m_touchFrames;
  if (touching && !m_touching) {
    ++m_warnings;
    if (m_firstWarning < 0) m_firstWarning = context.t;
    const Vec3& p = X_WT.position;
    if (context.events) context.events->log(context.t, "contact_warning", "touch", this, 0.0, {p.x(), p.y(), p.z()});
  }
  m_touching = touching;
}

void ContactWarning::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"queries", double(m_queries)});
  counters.push_back({"touch_frames", double(m_touchFrames)});
  counters.push_back({"warnings", double(m_warnings)});
  if (m_warnings > 0) counters.push_back({"first_warning_s", m_firstWarning});
}

}  // namespace trephine::haptics
