#include "LissajousDevice.h"

#include <cmath>
#include <numbers>

#include "framework/core/Lifecycle.h"

namespace lissajous {

void LissajousDevice::init(trephine::InitContext& context) {
  // The pose filter rejects motion faster than maxSpeed; a figure that fast
  // would hold its pose most of the time, so say so at load time instead.
  const trephine::Vec3 peakVelocity = 2.0 * std::numbers::pi * d_amplitude->cwiseProduct(d_frequency.value());  // mm/s
  if (peakVelocity.norm() > d_maxSpeed.value())
    context.error(d_frequency, "the figure moves at up to " + std::to_string(peakVelocity.norm()) +
                                   " mm/s, faster than maxSpeed (" + std::to_string(d_maxSpeed.value()) + " mm/s)");
}

trephine::DeviceSample LissajousDevice::readSample(double t) {
  const trephine::Vec3 phase = 2.0 * std::numbers::pi * t * d_frequency.value();  // rad
  const trephine::Vec3 position = d_center.value() + d_amplitude->cwiseProduct(phase.array().sin().matrix());
  return {t, position, trephine::Quat::Identity(), 0};
}

}  // namespace lissajous
