#include "plugins/haptics/ToolChange.h"

#include "framework/core/Lifecycle.h"
#include "framework/logs/EventLog.h"

namespace trephine::haptics {

void ToolChange::init(InitContext& context) {
  const bool byButton = d_button.value() > 0, byTime = d_time.value() >= 0, byEvent = !d_event.value().empty();
  if (int(byButton) + int(byTime) + int(byEvent) != 1)
    context.error(*this, "give exactly one of button (with device), time or event");
  if (byButton && !l_device) context.error(d_button, "a button needs the device that has it (device=\"@...\")");
  if (!byButton && l_device) context.error(l_device, "a device is only read for its button (set button)");
}

void ToolChange::tick(const TickContext& context) {
  if (m_changed) return;
  bool now = false;
  if (d_time.value() >= 0) {
    now = context.t >= d_time.value();
  } else if (!d_event.value().empty()) {
    // Events logged by any group so far (in this group: earlier in this frame, or the frame before).
    if (context.events)
      m_eventsRead = context.events->readSince(m_eventsRead, [&](const Event& e) { now = now || d_event.value() == e.kind; });
  } else {
    const DeviceState& device = l_device->state();
    const bool down = device.valid && ((device.buttons >> (d_button.value() - 1)) & 1u);
    now = down && !m_buttonWasDown;
    m_buttonWasDown = down;
  }
  if (!now) return;
  m_changed = true;
  m_changedAt = context.t;
  if (context.events)
    context.events->log(context.t, "tool_change",
                        d_time.value() >= 0 ? "time" : (d_event.value().empty() ? "button" : "event"), this, context.t);
}

void ToolChange::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"changed", m_changed ? 1.0 : 0.0});
  if (m_changed) counters.push_back({"changed_at_s", m_changedAt});
}

}  // namespace trephine::haptics
