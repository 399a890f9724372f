#pragma once
// The god-object proxy of a pointshell tool against a ShellContactTarget, as
// a component: each haptic frame it reads the device and the tool change,
// steps the proxy (stepProxy, ProxyStep.h, which says what a frame does), and
// keeps the memory and this frame's answer for ForceFeedback.
#include <vector>

#include "framework/geometry/ContactFrame.h"
#include "framework/geometry/ShellContactTarget.h"
#include "plugins/haptics/ProxyStep.h"
#include "plugins/haptics/ToolChange.h"

namespace trephine::haptics {

class GodObjectProxy final : public Component, public ContactFrameMember {
 public:
  static constexpr std::string_view kTypeName = "GodObjectProxy";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  // Queries its target, and the next one after a tool change.
  void joinContactFrame(ContactFrame& frame) override;
  // Every target the proxy moves a tool against (the first, the next one).
  std::vector<ShellContactTarget*> targets() const;
  void reportCounters(std::vector<Counter>& counters) const override;

  const ProxyState& state() const { return m_memory.state; }
  // What the proxy keeps from one frame to the next.
  const ProxyMemory& memory() const { return m_memory; }
  const ProxySettings& settings() const { return m_settings; }
  // The tool and target of this frame (the next ones after a tool change).
  ShellTool& tool() const { return *m_tool; }
  // Every tool the proxy moves: the tool, then the one after the change.
  std::vector<const ShellTool*> tools() const;
  // Which of tools() is in hand (no allocation: for the haptic loop).
  int toolIndex() const { return m_tool == &*l_tool ? 0 : 1; }
  bool changedTools() const { return m_changedTools; }
  // The displayed tool's orientation (the device's; the proxy moves its
  // position only): the last valid device pose's, identity before.
  const Quat& orientation() const { return m_orientation; }
  bool hasToolChange() const { return bool(l_toolChange); }
  // What this frame's target takes (ShellContactTarget::respond) once the
  // force rendered to the user is known (N, on the tool): its opposite onto
  // the target (a deformable one passes it on to its nodes) and, while the
  // drill runs, the burr loaded against it, with what this frame's collide()
  // returned (in the tool's ContactMemory). Zero force without contact.
  ContactResponse response(const Vec3& forceOnTool_N, double t);
  ShellContactTarget& target() const { return *m_target; }

 private:
  void changeTools(const TickContext& context);
  void checkTissueAction(InitContext& context, const ShellTool& tool, const ShellContactTarget& target,
                         const BaseField& at);

  Link<ShellTool> l_tool{this, "tool", {.help = "Pointshell tool moved by the device", .required = true}};
  Link<ShellContactTarget> l_target{this, "target", {.help = "What the tool collides with", .required = true}};
  EnumField d_sweep{this,
                    "sweep",
                    {"line", "cylinder", "spheres", "none"},
                    "line",
                    {.help = "How the path of the tool is swept before it moves: its leading point, a cylinder of "
                             "lines, the whole shell at steps, or not at all (the proxy jumps to the device)"}};
  Field<bool> d_rectify{
      this, "rectify", true, {.help = "Sweep again from the proxy to its god-object position before moving it"}};
  Field<bool> d_godObject{this,
                          "godObject",
                          true,
                          {.help = "Project the device on the constraint plane so the proxy slides on the surface "
                                   "(visual feedback); off keeps the proxy where the sweep left it"}};
  Field<int> d_drillButton{this,
                           "drillButton",
                           0,
                           {.help = "0: the tool cuts whenever the target can be drilled; n: only while device "
                                    "button n is held (a foot pedal)",
                            .min = 0.0,
                            .max = 32.0}};
  Link<ToolChange> l_toolChange{
      this,
      "toolChange",
      {.help = "From this tool change on, the proxy moves nextTool against nextTarget (the procedure's next phase)"}};
  Link<ShellTool> l_nextTool{
      this, "nextTool", {.help = "The tool after the change (the same device's); unset keeps the tool"}};
  Link<ShellContactTarget> l_nextTarget{
      this, "nextTarget", {.help = "What the tool collides with after the change; unset keeps the target"}};
  RateField d_rate{this, 1000.0, "Haptic rate"};

  ShellTool* m_tool = nullptr;        // l_tool, then l_nextTool
  ShellContactTarget* m_target = nullptr;  // l_target, then l_nextTarget
  bool m_changedTools = false;
  Quat m_orientation = Quat::Identity();

  ProxySettings m_settings;  // the fields, read once at init
  double m_shellSag = 0, m_nextShellSag = 0;  // mm, shellSag() of the tool and the next tool
  ProxyMemory m_memory;
  // The tool's memory for its queries of the target (reserveShell()), the
  // first tool's against the first target, then the next ones'.
  ContactMemory m_contactMemory, m_nextContactMemory;
  ProxyFrame m_frame;  // this frame's answer: what response() gives the target
};

}  // namespace trephine::haptics
