#pragma once
// Penalty force of a sphere tool against an implicit surface: with penetration
// p = radius - distance(centre) > 0 the force is F = k p n - b (v.n) n (never
// pulling), clamped to maxForce. The proxy is the sphere moved back onto the
// surface. Writes the haptic trace and publishes its values for a Recorder.
#include "framework/channels/Channel.h"
#include "framework/core/SampleSource.h"
#include "framework/geometry/ImplicitSurface.h"
#include "framework/logs/HapticFrameLog.h"
#include "plugins/haptics/SphereTool.h"

namespace trephine::haptics {

class SpringForce final : public Component, public SampleSource {
 public:
  static constexpr std::string_view kTypeName = "SpringForce";

  void init(InitContext& context) override;
  void tick(const TickContext& context) override;
  std::vector<std::string> sampleColumns() const override;

 private:
  Link<SphereTool> l_tool{this, "tool", {.help = "Sphere tool pressed into the target", .required = true}};
  Link<ImplicitSurface> l_target{this, "target", {.help = "Surface the tool touches", .required = true}};
  Field<double> d_stiffness{this, "stiffness", 2.0, {.help = "Spring stiffness k", .unit = "N/mm", .min = 0.0}};
  Field<double> d_damping{this, "damping", 0.002, {.help = "Damping b along the normal", .unit = "N*s/mm", .min = 0.0}};
  Field<double> d_maxForce{
      this, "maxForce", 3.3, {.help = "Largest force sent to the device", .unit = "N", .min = 0.0}};
  RateField d_rate{this, 1000.0, "Haptic rate"};

  HapticFrameLog* m_log = nullptr;
  Channel<Sample>* m_samples = nullptr;
};

}  // namespace trephine::haptics
