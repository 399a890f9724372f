#pragma once
// The moment a procedure changes tools (thesis section 6.4: the craniotomy
// ends, the brain interaction begins): at a time, when a device button is
// pressed, or when an event of a given kind is logged (the burr breaking
// through the bone, say), whichever the scene gives. A GodObjectProxy that links here
// (toolChange) moves to its next tool and target from that frame on, and a
// ContactWarning that links here stops; the change is logged as a
// "tool_change" event. It happens once.
#include "framework/core/Component.h"
#include "framework/devices/HapticDevice.h"

namespace trephine::haptics {

class ToolChange final : public Component {
 public:
  static constexpr std::string_view kTypeName = "ToolChange";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

  // True from the frame of the change on (read by components of this rate group).
  bool changed() const { return m_changed; }

 private:
  Link<HapticDevice> l_device{this, "device", {.help = "The device whose button changes tools (with button)"}};
  Field<int> d_button{this,
                      "button",
                      0,
                      {.help = "Change when this device button (1-based) is pressed; 0: no button",
                       .min = 0.0,
                       .max = 32.0}};
  Field<double> d_time{
      this, "time", -1.0, {.help = "Change at this time; negative: no time", .unit = "s"}};
  Field<std::string> d_event{this,
                             "event",
                             "",
                             {.help = "Change in the frame after an event of this kind is logged (breakthrough, "
                                      "contact_warning, ...); empty: no event"}};
  RateField d_rate{this, 1000.0, "The haptic rate (the proxy reads the change in the same frame)"};

  bool m_changed = false;
  size_t m_eventsRead = 0;      // events of the log already looked at
  bool m_buttonWasDown = true;  // a button held from the start is not a press
  double m_changedAt = -1;      // s
};

}  // namespace trephine::haptics
