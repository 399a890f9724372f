#pragma once
// A simulated hand holding the device handle, so that force and motion close
// the loop at the device rate: each frame the handle moves under the force
// rendered last frame (held, as a real device holds it), the pull of the grip
// toward where the hand means to be, and the device's own friction (see
// HandModel). Where the hand means to be is a ScriptedDevice's path (`intent`),
// so every scripted motion can be a hand's target; the buttons are its
// `buttonTimes`. The handle starts at rest at the intent's first point. The
// base class derives the velocity from consecutive poses, as for a real device.
#include "framework/devices/HapticDevice.h"
#include "plugins/haptics/HandModel.h"
#include "plugins/haptics/ScriptedDevice.h"

namespace trephine::haptics {

class HandDevice final : public HapticDevice {
 public:
  static constexpr std::string_view kTypeName = "HandDevice";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;

  // The damping that acts on the handle: the mechanism's and the grip's.
  std::optional<double> physicalDamping() const override { return d_deviceDamping.value() + d_gripDamping.value(); }
  std::string physicalDampingFields() const override { return "deviceDamping + gripDamping"; }

  const HandModel& hand() const { return m_hand; }

 protected:
  DeviceSample readSample(double t) override;

 private:
  Link<ScriptedDevice> l_intent{
      this, "intent", {.help = "Scripted device whose path is where the hand means to be", .required = true}};
  Field<double> d_deviceMass{this,
                             "deviceMass",
                             0.045,
                             {.help = "Apparent mass of the handle (the Phantom Omni's datasheet: 45 g at the tip)",
                              .unit = "kg",
                              .min = 0.0,
                              .minExclusive = true}};
  Field<double> d_deviceDamping{
      this,
      "deviceDamping",
      0.0,
      {.help = "Viscous friction of the mechanism. The Omni's datasheet gives none; 0 leaves the grip as the only "
               "damping, the cautious case for the sampled-data passivity check",
       .unit = "N*s/mm",
       .min = 0.0}};
  Field<double> d_handMass{this,
                           "handMass",
                           0.554,
                           {.help = "Mass of the hand and arm moving with the handle (van Beek et al. 2015, Sci Rep "
                                    "5:18004, arm holding a haptic device's handle, typical fit: 0.554 kg)",
                            .unit = "kg",
                            .min = 0.0}};
  Field<double> d_gripStiffness{this,
                                "gripStiffness",
                                0.135,
                                {.help = "Pull toward the intended position (van Beek et al. 2015, typical fit: "
                                         "135 N/m)",
                                 .unit = "N/mm",
                                 .min = 0.0}};
  Field<double> d_gripDamping{this,
                              "gripDamping",
                              0.00645,
                              {.help = "Pull toward the intended velocity (van Beek et al. 2015, typical fit: "
                                       "6.45 N*s/m)",
                               .unit = "N*s/mm",
                               .min = 0.0}};
  Field<int> d_substeps{
      this,
      "substeps",
      10,
      {.help = "Integration steps per frame; the rendered force is held over all of them", .min = 1.0, .max = 10000.0}};

  HandParameters m_parameters;  // the fields above, read once in init
  HandModel m_hand;
  double m_t = 0;  // s, time the hand has been integrated to
};

}  // namespace trephine::haptics
