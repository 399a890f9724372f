#include "framework/devices/HapticDevice.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "framework/core/AtomicFile.h"
#include "framework/core/Lifecycle.h"
#include "framework/devices/DeviceStream.h"
#include "framework/logs/EventLog.h"

namespace trephine {

void HapticDevice::prepare(const RunPlan& plan) {
  m_recorded.assign(d_record.value() || plan.keepDeviceInput ? plan.callsAt(rateHz()) : 0, DeviceSample{});
  m_recordedSize = 0;
  m_resets.assign(m_recorded.empty() ? 0 : kMostRecordedResets, 0.0);
  m_resetCount = 0;
  m_replacement.rewind();
  m_nextReset = 0;
}

void HapticDevice::replaceInput(std::vector<DeviceSample> stream, std::vector<double> resets) {
  m_replacement = DeviceStreamPlayer(std::move(stream));
  std::sort(resets.begin(), resets.end());
  m_replacementResets = std::move(resets);
}

void HapticDevice::tick(const TickContext& context) {
  m_tickEvents = context.events;
  DeviceSample raw;
  if (m_replacement.empty()) {
    raw = readSample(context.t);
  } else {
    raw = m_replacement.at(context.t);
    raw.t = context.t;
    // The replayed run took this sample without the jump test: so does this one.
    while (m_nextReset < m_replacementResets.size() && m_replacementResets[m_nextReset] <= context.t + 1e-9) {
      if (std::abs(m_replacementResets[m_nextReset] - context.t) <= 1e-9) forgetLastSample();
      ++m_nextReset;
    }
  }
  m_tickEvents = nullptr;
  if (m_replacement.empty() && !connected()) return;
  ++m_samples;
  if (m_recordedSize < m_recorded.size()) {
    m_recorded[m_recordedSize++] = raw;
    if (m_forgetPending && m_resetCount < m_resets.size()) m_resets[m_resetCount++] = raw.t;
  }
  m_forgetPending = false;

  const SampleVerdict verdict = m_filter.check(raw, d_maxSpeed.value(), context.dt);
  if (verdict != SampleVerdict::Accepted) {
    // Hold the whole last valid state (pose and velocity), so the force computed
    // from it is held too instead of jumping when the damping term drops out.
    if (verdict == SampleVerdict::NonFinite) {
      ++m_rejectedNonFinite;
    } else {
      ++m_rejectedJump;
    }
    // One event when a streak of rejections starts; the counters have the totals,
    // so a device stuck on NaN cannot fill the event log.
    if (context.events && !m_rejecting)
      context.events->log(context.t, "device_rejected", verdict == SampleVerdict::NonFinite ? "non_finite" : "jump",
                          this);
    m_rejecting = true;
    return;
  }
  if (m_rejecting && context.events) context.events->log(context.t, "device_recovered", "", this);
  m_rejecting = false;
  const DeviceSample previous = m_filter.last();
  const bool hadPrevious = m_filter.hasLast();
  m_filter.accept(raw);
  m_state.velocity = hadPrevious && raw.t > previous.t ? Vec3((raw.position - previous.position) / (raw.t - previous.t))
                                                       : Vec3::Zero();
  m_state.t = raw.t;
  m_state.pose.position = raw.position;
  m_state.pose.orientation = raw.orientation.normalized();
  m_state.buttons = raw.buttons;
  m_state.valid = true;
}

void HapticDevice::finish(FinishContext& context) {
  if (!d_record.value() || context.outputDirectory().empty()) return;
  const std::string name = FinishContext::defaultFileName("device", *this);
  if (!context.claimOutput(*this, name)) return;
  try {
    writeFileAtomically(context.outputDirectory() / name,
                        [&](std::ostream& out) { writeDeviceStream(out, m_recorded, m_recordedSize); });
  } catch (const FileWriteError& e) {
    context.error(*this, e.what());
  }
}

void HapticDevice::declareOutputs(std::vector<OutputFile>& outputs) const {
  if (d_record.value()) outputs.push_back({FinishContext::defaultFileName("device", *this), &d_record});
}

void HapticDevice::reportCounters(std::vector<Counter>& counters) const {
  counters.push_back({"samples", static_cast<double>(m_samples)});
  counters.push_back({"rejected_non_finite", static_cast<double>(m_rejectedNonFinite)});
  counters.push_back({"rejected_jump", static_cast<double>(m_rejectedJump)});
}

}  // namespace trephine
