#pragma once
// Colgate and Schenkelberg (1997), "Factors affecting the Z-width of a haptic
// display": a virtual wall of stiffness K and virtual damping B, rendered
// with sample period T through a zero-order hold on a device whose handle has
// physical damping b, is passive if and only if
//
//   b > K T / 2 + |B|.
//
// The sampling and hold delay the spring by about T/2, which acts like a
// negative damping K T / 2; a damping computed from backward differences can
// add energy at high frequency, up to |B|. Only the device's real damping can
// pay for both.
#include <string>

namespace trephine {
class BaseField;
class HapticDevice;
class InitContext;
}  // namespace trephine

namespace trephine::haptics {

struct PassivityVerdict {
  bool passive = false;
  double requiredDamping = 0;   // N*s/mm, K T / 2 + |B|: b must exceed it
  double largestStiffness = 0;  // N/mm, 2 (b - |B|) / T (0 when b <= |B|): K must stay below it
};

// K in N/mm, B and b in N*s/mm, the rendering rate in Hz (T = 1 / rate).
PassivityVerdict sampledDataPassivity(double stiffness, double virtualDamping, double rateHz, double physicalDamping);

// N*s/mm: a desktop haptic device's own damping, taken high, for the check
// of a device that models none: it catches a slip of units (N/m typed as
// N/mm), not a marginal gain.
inline constexpr double kGenerousDeviceDamping = 0.01;

// Warns at `stiffnessField` when the rendering (K, B at rateHz) is not
// passive on `device`: on its physical damping where it reports one, else
// (scripted, replayed) on kGenerousDeviceDamping.
void warnIfNotPassive(InitContext& context, const BaseField& stiffnessField, double stiffness, double virtualDamping,
                      double rateHz, const HapticDevice& device);

}  // namespace trephine::haptics
