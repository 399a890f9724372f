#pragma once
// Warns when a tool touches what it must not (thesis section 6.4: during the
// craniotomy the burr reaching the brain is reported, with no force and no
// deformation): each frame it asks the target whether the proxy's tool, where
// the proxy shows it (held by the bone it drills, not where the hand pushes
// the device), overlaps it, and logs a "contact_warning" event (time, tool
// position) when a touch begins. With a ToolChange (until) it stops asking
// from the change on. Nothing else queries the target for it.
#include "framework/core/Component.h"
#include "framework/geometry/ContactFrame.h"
#include "framework/geometry/ShellContactTarget.h"
#include "plugins/haptics/GodObjectProxy.h"
#include "plugins/haptics/ToolChange.h"

namespace trephine::haptics {

class ContactWarning final : public Component, public ContactFrameMember {
 public:
  static constexpr std::string_view kTypeName = "ContactWarning";
  void joinContactFrame(ContactFrame& frame) override { frame.queries(*l_target); }

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;

 private:
  Link<GodObjectProxy> l_proxy{this, "proxy", {.help = "The proxy whose tool is watched", .required = true}};
  Link<ShellContactTarget> l_target{this, "target", {.help = "What it must not touch", .required = true}};
  Link<ToolChange> l_until{this, "until", {.help = "Stop watching from this tool change on"}};
  RateField d_rate{this, 1000.0, "Rate of the check (the haptic rate: a touch shorter than a frame is not missed)"};

  bool m_touching = false;
  uint64_t m_queries = 0, m_touchFrames = 0, m_warnings = 0;
  double m_firstWarning = -1;  // s
};

}  // namespace trephine::haptics
