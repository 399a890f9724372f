#include "plugins/haptics/HandDevice.h"

#include "framework/core/Lifecycle.h"
#include "framework/core/Strings.h"

namespace trephine::haptics {

void HandDevice::init(InitContext& context) {
  m_parameters.deviceMass = d_deviceMass.value();
  m_parameters.deviceDamping = d_deviceDamping.value();
  m_parameters.handMass = d_handMass.value();
  m_parameters.gripStiffness = d_gripStiffness.value();
  m_parameters.gripDamping = d_gripDamping.value();
  // The grip's spring and dampers are integrated in substeps; too few for a
  // light, stiff hand and the integration itself would oscillate.
  if (!m_parameters.integratesStably(rateHz(), d_substeps.value()))
    context.error(d_substeps, std::to_string(d_substeps.value()) + " steps per frame at " + formatDouble(rateHz()) +
                                  " Hz are too coarse for a " + formatDouble(m_parameters.mass()) +
                                  " kg hand with this grip; raise substeps");
}

void HandDevice::prepare(const RunPlan& plan) {
  HapticDevice::prepare(plan);
  m_hand.reset(l_intent->scriptedPath().at(0.0));
  m_t = 0;
}

DeviceSample HandDevice::readSample(double t) {
  // The force rendered last frame has been held since then (zero-order hold).
  if (t > m_t) {
    m_hand.advance(m_parameters, l_intent->scriptedPath(), m_t, t - m_t, d_substeps.value(), commandedForce());
    m_t = t;
  }
  return DeviceSample{t, m_hand.position(), Quat::Identity(), l_intent->buttonsAt(t)};
}

}  // namespace trephine::haptics
