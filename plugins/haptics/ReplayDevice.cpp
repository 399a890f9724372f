#include "plugins/haptics/ReplayDevice.h"

#include <cmath>
#include <cstdio>

#include "framework/core/Lifecycle.h"
#include "framework/core/Strings.h"
#include "framework/devices/DeviceStream.h"

namespace trephine::haptics {

void ReplayDevice::init(InitContext& context) {
  DeviceStreamReadResult read = readDeviceStream(d_file.path());
  if (!read.error.empty()) {
    context.error(d_file, read.error);
    return;
  }
  for (DeviceSample& s : read.samples) s.position += d_offset.value();
  m_stream = DeviceStreamPlayer(std::move(read.samples));
  if (auto problem = timesProblem()) context.error(d_file, d_file.path().string() + ": " + *problem);
}

std::optional<std::string> ReplayDevice::timesProblem() const {
  // Times are seconds from the run's start. A recording in other units, or
  // in a clock of its own, would otherwise replay as no motion at all (all
  // before the start, or after the longest run) or crushed into a few frames.
  const std::vector<DeviceSample>& samples = m_stream.samples();
  const double first = samples.front().t, last = samples.back().t;
  const std::string units = " (the column t is in seconds from the start of the run)";
  if (last < 0) return "every sample is before the run starts at t = 0 (the last at " + formatDouble(last) + " s)" + units;
  if (first > RunPlan::kMaxDuration)
    return "the first sample is at " + formatDouble(first) + " s, after the longest run (" +
           formatDouble(RunPlan::kMaxDuration) + " s)" + units;
  if (samples.size() < 2) return std::nullopt;
  const double period = 1.0 / rateHz();
  const double spacing = (last - first) / double(samples.size() - 1);  // s, mean between samples
  if (spacing < 0.01 * period) {
    char text[160];
    std::snprintf(text, sizeof text, "%zu samples over %.3g s are %.3g s apart", samples.size(), last - first,
                  spacing);
    return text + (", a hundredth of the device's period (" + formatDouble(period) +
                   " s) or less: are the times in milliseconds, microseconds or nanoseconds?") +
           units;
  }
  return std::nullopt;
}

void ReplayDevice::prepare(const RunPlan& plan) {
  HapticDevice::prepare(plan);
  m_stream.rewind();
  m_pass = 0;
  // One pass lasts from the first sample to one period after the last.
  m_loopSpan = m_stream.samples().back().t - m_stream.samples().front().t + 1.0 / rateHz();
}

double ReplayDevice::preferredDuration() const {
  // A looping replay has no natural end: the run length comes from --duration or other components.
  if (m_stream.empty() || d_loop.value()) return 0;
  return m_stream.samples().back().t + 1.0 / rateHz();
}

DeviceSample ReplayDevice::readSample(double scheduledT) {
  // With loop, the recording is looked up at a wrapped time; the sample keeps
  // the scheduled time so that time never runs backwards in the run.
  double t = scheduledT;
  const double first = m_stream.samples().front().t, last = m_stream.samples().back().t;
  if (d_loop.value() && t > last) {
    t = first + std::fmod(t - first, m_loopSpan);
    const uint64_t pass = static_cast<uint64_t>((scheduledT - first) / m_loopSpan);
    if (pass != m_pass) {
      m_pass = pass;
      forgetLastSample();  // jumping back to the start is intended, not a glitch
    }
  }
  DeviceSample sample = m_stream.at(t);
  sample.t = scheduledT;
  return sample;
}

}  // namespace trephine::haptics
