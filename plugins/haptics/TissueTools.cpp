#include "plugins/haptics/TissueTools.h"

#include "framework/core/Lifecycle.h"

namespace trephine::haptics {

void AspiratorTool::init(InitContext& context) {
  d_shape.build(context, m_points, m_boundingRadius);
  // Unit slips: a frequency in kHz, a power in mW.
  if (d_frequency.value() > 0 && d_frequency.value() < 1000)
    context.warning(d_frequency, "is in Hz: " + std::to_string(d_frequency.value()) +
                                     " Hz is not ultrasonic (handpieces vibrate at 23 or 36 kHz: 23000); kHz typed "
                                     "as Hz?");
  if (d_power.value() > 200)
    context.warning(d_power, "is in W: clinical handpieces are rated at 20 to 100 W; mW typed as W?");
}

void AspiratorTool::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"shell_points", static_cast<double>(m_points.size())});
  counters.push_back({"tip_speed_mm_per_s", tissueAction().tipSpeed_mm_per_s});
}

TissueAction AspiratorTool::tissueAction() const {
  TissueAction action;
  action.kind = TissueAction::Kind::kAspirate;
  // A sinusoidal stroke of amplitude A at f covers 4 A a period.
  action.tipSpeed_mm_per_s = 4.0 * d_amplitude.value() * d_frequency.value();
  action.coupling = d_coupling.value();
  action.power_W = d_power.value();
  action.pedal = d_pedal.value();
  return action;
}

void BipolarForceps::init(InitContext& context) {
  d_shape.build(context, m_points, m_boundingRadius);
  if (d_power.value() > 100)
    context.warning(d_power, "is in W: bipolar generators are set to 10 to 50 W, and only part of it reaches the "
                             "tissue; mW typed as W?");
}

void BipolarForceps::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"shell_points", static_cast<double>(m_points.size())});
}

TissueAction BipolarForceps::tissueAction() const {
  TissueAction action;
  action.kind = TissueAction::Kind::kCoagulate;
  action.power_W = d_power.value();
  action.pedal = d_pedal.value();
  return action;
}

}  // namespace trephine::haptics
