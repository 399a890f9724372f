#pragma once
// Steps ticking components in rate groups.
//
// Virtual time (default): one thread runs every group's calls in due-time
// order, t = k / rate; calls due at the same instant run highest rate first,
// and within a group in document order. Nothing depends on the wall clock,
// so a run is reproducible bit for bit.
//
// Real time: one thread per group, each paced to absolute deadlines
// t0 + k / rate. A step that ends after the next deadline is a deadline miss;
// after a stall the group skips the ticks it missed (counted as misses)
// instead of bursting to catch up. A group with a member that paces it (a
// FramePacer: a device outside the process) starts each frame when that
// member's input has come, not sooner than 3/4 of a period after the last
// frame's start and not later than 1.5 periods after it (one period after
// two frames without input: the clock's pace), so the answer goes back within
// the device's own frame; frames that waited out the bound are counted as
// unpaced.
//
// The scheduler times every call (one clock read per call: the end of one
// call is the start of the next). Components of one group share a thread;
// data crosses groups only through channels.
//
// Each step of a group owns the haptic frame's contact stage: its
// ContactFrame opens the frame before the first member ticks, the members
// (devices, then proxies, then force renderers: link targets tick before the
// components that read them) query the targets through it and leave their
// responses in it, and after the last member it hands every target its
// frame's responses in one call.
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "framework/core/Component.h"
#include "framework/core/Lifecycle.h"
#include "framework/geometry/ContactFrame.h"
#include "framework/runtime/TimingHistogram.h"

namespace trephine {

class FramePacer;

struct GroupMember {
  Component* component = nullptr;
  TimingHistogram histogram;
  std::vector<float> callUs;  // duration (µs) per tick index, preallocated; NaN for a skipped tick
  uint64_t calls = 0;
  uint64_t overruns = 0;  // calls that alone took longer than the group period
};

struct RateGroup {
  double rateHz = 0;
  std::string name;  // "" for the rate's own group, else the components' `group`
  double periodS = 0;
  uint64_t plannedCalls = 0;
  std::vector<GroupMember> members;  // document order
  TimingHistogram stepHistogram;     // whole group step
  TimingHistogram wakeLateness;      // real time: wake-up time minus deadline
  uint64_t calls = 0;
  uint64_t deadlineMisses = 0;
  uint64_t skippedTicks = 0;  // real time: ticks dropped after a stall
  double wallSeconds = 0;     // real time: from first deadline to the end
  uint64_t firstStartNs = 0, lastStartNs = 0;  // real time: clock at the first and the last step

  // Real time: steps per second actually achieved, (calls - 1) / (last start - first start).
  double callsPerSecond() const {
    return calls > 1 && lastStartNs > firstStartNs
               ? static_cast<double>(calls - 1) / (static_cast<double>(lastStartNs - firstStartNs) * 1e-9)
               : 0.0;
  }
  bool realtimePriority = false;
  // Real time, a paced group: frames started by the pacer's input, and
  // frames started by the clock's bound with none come.
  FramePacer* pacer = nullptr;
  uint64_t pacedFrames = 0, unpacedFrames = 0;
  uint64_t unpacedRun = 0;  // unpaced frames in a row
  // The group's contact stage: begun before its members tick, ended (every
  // target its responses) after them (ContactFrame.h).
  ContactFrame contacts;
  const GroupMember* current = nullptr;  // the member being ticked
  double currentT = 0;                   // s, scheduled time of the step being run
};

class Scheduler {
 public:
  Scheduler(const std::vector<Component*>& components, const RunPlan& plan, EventLog* events);

  // Runs until the planned duration is simulated or `stop` becomes true.
  void run(const std::atomic<bool>& stop);

  const std::vector<RateGroup>& groups() const { return m_groups; }
  // The rate's own group (not a named one), or null.
  const RateGroup* group(double rateHz) const;
  double simulatedTime() const { return m_simulatedTime; }  // s
  // The simulated time reached so far (s), readable from any thread while
  // run() goes on (a relaxed atomic the stepping thread stores after each
  // step of the fastest group in real time, of any group in virtual time).
  double progress() const { return m_progress.load(std::memory_order_relaxed); }
  bool completed() const { return m_completed; }
  // Set when a component threw during a tick: "path: message".
  const std::optional<std::string>& failure() const { return m_failure; }

 private:
  void runVirtual(const std::atomic<bool>& stop);
  void runRealtime(const std::atomic<bool>& stop);
  // Runs one step of `group` at call index k; returns its duration (ns).
  uint64_t step(RateGroup& group, uint64_t k);
  // Real time: frame k of a paced group, started as FramePacer.h says.
  void stepPaced(RateGroup& group, uint64_t k, uint64_t t0, const std::atomic<bool>& stop);
  // "path: what", and a tick_failed event.
  std::string describeFailure(const RateGroup& group, const char* what);

  RunPlan m_plan;
  EventLog* m_events;
  std::vector<RateGroup> m_groups;  // highest rate first
  double m_simulatedTime = 0;
  std::atomic<double> m_progress{0};
  bool m_completed = false;
  std::optional<std::string> m_failure;
};

}  // namespace trephine
