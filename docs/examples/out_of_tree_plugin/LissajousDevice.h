#pragma once
// A simulated device tracing a Lissajous figure: each axis oscillates about
// `center` with its own amplitude and frequency,
//   p(t) = center + amplitude * sin(2 pi frequency t)   (per axis, mm),
// for `duration` seconds. With a plane under the centre and a z amplitude
// larger than the tool's clearance, the tool touches and leaves the surface
// periodically, which exercises contact onset and release.
#include <string_view>

#include "framework/devices/HapticDevice.h"

namespace lissajous {

class LissajousDevice final : public trephine::HapticDevice {
 public:
  static constexpr std::string_view kTypeName = "LissajousDevice";

  void init(trephine::InitContext& context) override;
  double preferredDuration() const override { return d_duration.value(); }

 protected:
  trephine::DeviceSample readSample(double t) override;

 private:
  trephine::Field<trephine::Vec3> d_center{
      this, "center", trephine::Vec3::Zero(), {.help = "Centre of the figure", .unit = "mm"}};
  trephine::Field<trephine::Vec3> d_amplitude{this,
                                              "amplitude",
                                              trephine::Vec3(10, 10, 0),
                                              {.help = "Half the swing along x, y and z", .unit = "mm", .min = 0.0}};
  trephine::Field<trephine::Vec3> d_frequency{
      this,
      "frequency",
      trephine::Vec3(1, 2, 0),
      {.help = "Oscillation frequency along x, y and z", .unit = "Hz", .min = 0.0}};
  trephine::Field<double> d_duration{this,
                                     "duration",
                                     2.0,
                                     {.help = "Length of the motion, used as the run length when none is given",
                                      .unit = "s",
                                      .min = 0.0,
                                      .minExclusive = true}};
};

}  // namespace lissajous
