#pragma once
// A haptic device as the simulation sees it: each tick it reads a raw sample
// (position mm, orientation, buttons), rejects what cannot be a real hand
// motion (NaN, Inf, a jump faster than `maxSpeed`), holds the last valid pose
// when it rejects one, and records the raw stream so the run can be replayed
// exactly with a ReplayDevice. Force goes back through applyForce().
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Component.h"
#include "framework/devices/DevicePoseFilter.h"
#include "framework/devices/DeviceStreamPlayer.h"
#include "framework/devices/DeviceSample.h"

namespace trephine {

struct DeviceState {
  double t = 0;                  // s, time of the last accepted sample
  Pose pose;                     // X_WD, mm
  Vec3 velocity = Vec3::Zero();  // mm/s, from the last two accepted poses
  uint32_t buttons = 0;
  bool valid = false;  // false until a first sample was accepted
};

class HapticDevice : public Component {
 public:
  static constexpr std::string_view kTypeName = "HapticDevice";

  const DeviceState& state() const { return m_state; }
  // The force the simulation sends to the hand (N, world frame). A hardware
  // device forwards it; simulated devices keep it for inspection.
  virtual void applyForce(const Vec3& force_N) { m_commandedForce = force_N; }
  const Vec3& commandedForce() const { return m_commandedForce; }

  // The damping that acts on the handle (N*s/mm) when the device models its
  // dynamics, and the fields it comes from ("deviceDamping + gripDamping"), for
  // the sampled-data passivity check of force renderers. Scripted and replayed
  // devices have no dynamics: nothing to check against.
  virtual std::optional<double> physicalDamping() const { return std::nullopt; }
  virtual std::string physicalDampingFields() const { return {}; }

  // Whether the device is outside the process (a device program, a tracker):
  // it moves in wall time, so a run without --realtime does not wait for it
  // and the load warns (such a device opens its connections only in real time).
  virtual bool outsideTheProcess() const { return false; }

  // Subclasses that override these must call the HapticDevice versions
  // (they allocate the recording and report the rejection counters).
  void prepare(const RunPlan& plan) override;
  void tick(const TickContext& context) final;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void declareOutputs(std::vector<OutputFile>& outputs) const override;

  // The raw stream this run has read so far (empty unless `record` or the
  // plan's keepDeviceInput).
  std::span<const DeviceSample> recorded() const { return {m_recorded.data(), m_recordedSize}; }
  // From the next prepare() on, the device reads `stream` (another run's
  // recorded input, played as ReplayDevice plays a file) instead of its own
  // input, and records it as its own: a study runs every setting on the
  // reference setting's motion this way, whatever path the device would have
  // planned against this setting's model. A device whose motion answers the
  // force (a simulated hand) then moves as it did in that run, open loop.
  // `resets`: the times (s, sample times of `stream`) at which that run's
  // device took its sample without the jump test (forgetLastSample: a
  // looping replay starting over), so that the replay does the same.
  void replaceInput(std::vector<DeviceSample> stream, std::vector<double> resets = {});
  bool inputReplaced() const { return !m_replacement.empty(); }
  // The sample times this run took without the jump test (recorded with the
  // stream; at most kMostRecordedResets).
  std::span<const double> recordedResets() const { return {m_resets.data(), m_resetCount}; }
  static constexpr size_t kMostRecordedResets = 4096;

  // Samples received and rejected so far.
  uint64_t samples() const { return m_samples; }
  uint64_t rejectedNonFinite() const { return m_rejectedNonFinite; }
  uint64_t rejectedJump() const { return m_rejectedJump; }

 protected:
  // The raw device reading at time t (s). Must not allocate or throw.
  virtual DeviceSample readSample(double t) = 0;
  // The run's event log during tick() (readSample may log through it), else null.
  EventLog* tickEvents() const { return m_tickEvents; }
  // Whether a device is there to read. A device outside the process is not
  // until its first sample has come: tick() then takes nothing from
  // readSample (the state stays invalid, nothing is counted or recorded).
  virtual bool connected() const { return true; }
  // The next sample is taken as it comes, without the jump test (an intended
  // discontinuity, such as a looping replay starting over).
  void forgetLastSample() {
    m_filter.forget();
    m_forgetPending = true;
  }

  RateField d_rate{this, 1000.0, "Rate at which the device is read"};
  Field<double> d_maxSpeed{this,
                           "maxSpeed",
                           5000.0,
                           {.help = "Fastest plausible motion; a faster jump is rejected and the last pose held",
                            .unit = "mm/s",
                            .min = 0.0,
                            .minExclusive = true}};
  Field<bool> d_record{this, "record", true, {.help = "Write the raw device stream to device.<path with / as .>.csv"}};

 private:
  DeviceState m_state;
  Vec3 m_commandedForce = Vec3::Zero();
  DevicePoseFilter m_filter;
  DeviceStreamPlayer m_replacement;     // replaceInput's stream (empty: the device's own input)
  std::vector<double> m_replacementResets;  // its resets' times, ascending
  size_t m_nextReset = 0;
  std::vector<double> m_resets;  // preallocated in prepare(): the times of this run's resets
  size_t m_resetCount = 0;
  bool m_forgetPending = false;  // forgetLastSample() during this tick's read
  std::vector<DeviceSample> m_recorded;  // preallocated in prepare()
  size_t m_recordedSize = 0;
  uint64_t m_samples = 0, m_rejectedNonFinite = 0, m_rejectedJump = 0;
  bool m_rejecting = false;  // inside a streak of rejected samples
  EventLog* m_tickEvents = nullptr;
};

}  // namespace trephine
