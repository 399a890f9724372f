#include "plugins/haptics/TissueTools.h"

#include "framework/core/Lifecycle.h"

namespace trephine::haptics {

void AspiratorTool::init(InitContext& context) { d_shape.build(context, m_points, m_boundingRadius); }

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

void BipolarForceps::init(InitContext& context) { d_shape.build(context, m_points, m_boundingRadius); }

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
