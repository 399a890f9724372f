#include "plugins/haptics/SampledDataPassivity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "framework/core/Lifecycle.h"
#include "framework/devices/HapticDevice.h"

namespace trephine::haptics {

namespace {
// Six significant digits: sums such as 0.0015 + 0.002 print as 0.0035.
std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}
}  // namespace

PassivityVerdict sampledDataPassivity(double stiffness, double virtualDamping, double rateHz, double physicalDamping) {
  const double period = 1.0 / rateHz;  // s
  PassivityVerdict verdict;
  verdict.requiredDamping = 0.5 * stiffness * period + std::abs(virtualDamping);
  verdict.largestStiffness = std::max(0.0, 2.0 * (physicalDamping - std::abs(virtualDamping)) / period);
  verdict.passive = physicalDamping > verdict.requiredDamping;
  return verdict;
}

void warnIfNotPassive(InitContext& context, const BaseField& stiffnessField, double stiffness, double virtualDamping,
                      double rateHz, const HapticDevice& device) {
  const std::optional<double> damping = device.physicalDamping();
  if (!damping) {
    // A scripted or replayed device stands for a real one: the rendering must
    // still be one a real device can keep passive (a stiffness in N/m typed
    // as N/mm is a thousand times too stiff, and chatters at the force limit).
    const PassivityVerdict typical = sampledDataPassivity(stiffness, virtualDamping, rateHz, kGenerousDeviceDamping);
    if (typical.passive) return;
    context.warning(stiffnessField,
                    "stiffness " + number(stiffness) + " N/mm with damping " + number(virtualDamping) + " N s/mm at " +
                        number(rateHz) + " Hz needs a physical damping above " + number(typical.requiredDamping) +
                        " N s/mm, more than a desktop haptic device has (taken generously as " +
                        number(kGenerousDeviceDamping) + "; " + device.path() +
                        " models none): largest passive stiffness " + number(typical.largestStiffness) +
                        " N/mm (sampled-data passivity, Colgate and Schenkelberg 1997: b > K T / 2 + |B|). Devices "
                        "render about 1 to 5 N/mm: is it in N/m, or the damping in N s/m?");
    return;
  }
  const PassivityVerdict verdict = sampledDataPassivity(stiffness, virtualDamping, rateHz, *damping);
  if (verdict.passive) return;
  context.warning(stiffnessField,
                  "stiffness " + number(stiffness) + " N/mm with damping " + number(virtualDamping) + " N s/mm at " +
                      number(rateHz) + " Hz needs a physical damping above " + number(verdict.requiredDamping) +
                      " N s/mm; " + device.path() + " has " + number(*damping) + " (" + device.physicalDampingFields() +
                      "): largest passive stiffness " + number(verdict.largestStiffness) +
                      " N/mm (sampled-data passivity, Colgate and Schenkelberg 1997: b > K T / 2 + |B|)");
}

}  // namespace trephine::haptics
