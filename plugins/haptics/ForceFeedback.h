#pragma once
// The viscoelastic force of a god-object proxy contact (thesis Eq. 3.3):
//   F = k p n - b (v . n) n,
// with k the stiffness, p the rendered penetration, n the contact normal and
// v the device velocity. The damping acts along the normal only and opposes
// the motion (pressing in meets more resistance, pulling out less), and the
// force never pulls the hand into the target. The spring's share k p is capped
// at maxForce (the device-proxy gap counts up to maxForce / k, so a device
// pushed past the clamp stores nothing that pulling back must first undo, and
// the damping still acts at the clamp); |F| is then clamped to maxForce in the
// direction n, and, when maxForceStep > 0, the change of F between frames to
// maxForceStep (a last guard, counted as step_limited_frames when it acts).
// When the proxy is let go (what shapes its target failed, ProxyState::released),
// the force rendered then fades linearly to zero over releaseRamp.
// The force also loads the proxy's burr against the target (drilling).
// Writes the haptic trace and publishes its values for a Recorder.
#include "framework/channels/Channel.h"
#include "framework/core/SampleSource.h"
#include "framework/logs/HapticFrameLog.h"
#include "framework/geometry/ContactFrame.h"
#include "framework/geometry/HeldTools.h"
#include "plugins/haptics/GodObjectProxy.h"

namespace trephine::haptics {

class ForceFeedback final : public Component, public SampleSource, public HeldTools, public ContactFrameMember {
 public:
  static constexpr std::string_view kTypeName = "ForceFeedback";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  // Responds to its proxy's targets: the force on them and the cut.
  void joinContactFrame(ContactFrame& frame) override;
  // The gains of this frame (the next ones once the proxy changed tools), N/mm and N s/mm.
  double stiffness() const;
  double damping() const;
  void reportCounters(std::vector<Counter>& counters) const override;
  std::vector<std::string> sampleColumns() const override;
  std::vector<const ShellTool*> heldTools() const override { return l_proxy->tools(); }

  const Vec3& force() const { return m_force; }

 private:
  double stiffnessAfterChange() const;
  double dampingAfterChange() const;

  Link<GodObjectProxy> l_proxy{this, "proxy", {.help = "Proxy whose contact is rendered", .required = true}};
  Field<double> d_stiffness{this, "stiffness", 2.0, {.help = "Stiffness k", .unit = "N/mm", .min = 0.0}};
  Field<double> d_damping{
      this, "damping", 0.002, {.help = "Viscosity b along the contact normal", .unit = "N*s/mm", .min = 0.0}};
  Field<double> d_nextStiffness{this,
                                "nextStiffness",
                                -1.0,
                                {.help = "After the proxy's tool change: the stiffness for the next tool and target "
                                         "(a soft brain after the bone); negative keeps stiffness",
                                 .unit = "N/mm"}};
  Field<double> d_nextDamping{this,
                              "nextDamping",
                              -1.0,
                              {.help = "After the proxy's tool change: the damping; negative keeps damping",
                               .unit = "N s/mm"}};
  Field<double> d_maxForce{
      this,
      "maxForce",
      3.3,
      {.help = "Largest force sent to the device (3.3 N for a Phantom Omni)", .unit = "N", .min = 0.0}};
  Field<double> d_maxForceStep{
      this,
      "maxForceStep",
      0.0,
      {.help = "Largest change of the force vector between two frames; 0 for no limit", .unit = "N", .min = 0.0}};
  Field<bool> d_trace{this,
                      "trace",
                      true,
                      {.help = "Write this tool's frames to the run's trace.csv and the summary's haptics (one "
                               "tool per scene does); false: to trace.PATH.csv (PATH: this component's path with "
                               "dots for slashes). Every tool's figures are in the summary's tools"}};
  Field<double> d_releaseRamp{
      this,
      "releaseRamp",
      0.05,
      {.help = "When the proxy is let go because what shapes its target failed (a diverged FEM), the force "
               "rendered then fades to zero over this time, and no contact is rendered until the tool is clear "
               "of the target",
       .unit = "s",
       .min = 0.0}};
  RateField d_rate{this, 1000.0, "Haptic rate"};

  HapticFrameLog* m_log = nullptr;
  Channel<Sample>* m_samples = nullptr;
  Vec3 m_force = Vec3::Zero();
  size_t m_responder = 0;  // its slot in the group's contact frame
  uint64_t m_saturatedFrames = 0, m_stepLimitedFrames = 0;
  // The fade of the force after the proxy was let go: from m_rampFrom, frame
  // m_rampFrame of m_rampFrames (none running when they are equal).
  Vec3 m_rampFrom = Vec3::Zero();
  uint64_t m_rampFrames = 0, m_rampFrame = 0, m_releaseRamps = 0;
  bool m_wasReleased = false;
};

}  // namespace trephine::haptics
