#include "plugins/haptics/SpringForce.h"

#include <algorithm>

#include "framework/core/Lifecycle.h"

namespace trephine::haptics {

void SpringForce::init(InitContext& context) {
  m_log = context.claimHapticLog(*this);
  // The passivity observer counts the device's own damping too (a device with dynamics).
  if (m_log)
    if (const std::optional<double> b = l_tool->device().physicalDamping()) m_log->setDeviceDamping(*b);
  m_samples = &context.channels().publish<Sample>(*this, kSampleChannel);
}

std::vector<std::string> SpringForce::sampleColumns() const {
  return {"device_x", "device_y", "device_z", "proxy_x", "proxy_y",
          "proxy_z",  "force_x",  "force_y",  "force_z", "penetration"};
}

void SpringForce::tick(const TickContext& context) {
  const SphereTool& tool = *l_tool;
  const DeviceState& device = tool.device().state();
  HapticFrame frame;
  frame.t = context.t;
  frame.device = device.pose.position;
  frame.proxy = frame.device;
  if (device.valid) {
    const Vec3 center = tool.center();
    Vec3 normal;
    const double penetration = tool.radius() - l_target->signedDistance(center, normal);
    frame.proxy = center;
    if (penetration > 0) {
      // Spring along the normal plus damping of the normal velocity; a contact never pulls.
      const double normalSpeed = device.velocity.dot(normal);  // mm/s, negative when pressing in
      const double magnitude = std::max(0.0, d_stiffness.value() * penetration - d_damping.value() * normalSpeed);
      frame.force = std::min(magnitude, d_maxForce.value()) * normal;
      frame.proxy = center + penetration * normal;
      frame.penetration = penetration;
      frame.normal = normal;
      frame.contacts = 1;
    }
  }
  tool.device().applyForce(frame.force);
  if (m_log) m_log->record(frame);

  Sample sample;
  sample.t = context.t;
  const Vec3* vectors[] = {&frame.device, &frame.proxy, &frame.force};
  size_t k = 0;
  for (const Vec3* v : vectors)
    for (int i = 0; i < 3; ++i) sample.values[k++] = (*v)[i];
  sample.values[k] = frame.penetration;
  m_samples->publish(sample);
}

}  // namespace trephine::haptics
