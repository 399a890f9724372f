#pragma once
// Replays a device stream file (t,x,y,z,qw,qx,qy,qz,buttons; s, mm), such as
// the device.*.csv every run records. At a recorded time it returns exactly the
// recorded sample, so a run replayed at the same rate reproduces its trace;
// between samples it interpolates (linear position, spherical orientation).
#include <optional>
#include <string>

#include "framework/devices/DeviceStreamPlayer.h"
#include "framework/devices/HapticDevice.h"

namespace trephine::haptics {

class ReplayDevice final : public HapticDevice {
 public:
  static constexpr std::string_view kTypeName = "ReplayDevice";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  double preferredDuration() const override;

 protected:
  DeviceSample readSample(double scheduledT) override;

 private:
  // Why the recording's times cannot be seconds from the run's start, if they cannot.
  std::optional<std::string> timesProblem() const;
  FilePathField d_file{this, "file", {.help = "Device stream CSV (t,x,y,z,qw,qx,qy,qz,buttons)", .required = true}};
  Field<bool> d_loop{this, "loop", false, {.help = "Start again from the beginning after the last sample"}};
  Field<Vec3> d_offset{this, "offset", Vec3::Zero(), {.help = "Added to every recorded position", .unit = "mm"}};

  DeviceStreamPlayer m_stream;
  double m_loopSpan = 0;  // s
  uint64_t m_pass = 0;
};

}  // namespace trephine::haptics
