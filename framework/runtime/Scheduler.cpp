#include "framework/runtime/Scheduler.h"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <limits>
#include <map>
#include <mutex>
#include <thread>

#include "framework/core/FramePacer.h"

namespace trephine {

namespace {

using Clock = std::chrono::steady_clock;

inline uint64_t nowNs() {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count());
}

// Sleeps until `deadline` (ns, steady clock). The last `spinNs` are spent
// polling the clock instead: a timed sleep on a virtual machine wakes 40-60 µs
// late, too coarse for a 1 kHz loop, while polling is exact to the clock read.
void sleepUntilNs(uint64_t deadline, uint64_t spinNs) {
  const uint64_t wake = deadline > spinNs ? deadline - spinNs : 0;
  timespec ts{static_cast<time_t>(wake / 1000000000ull), static_cast<long>(wake % 1000000000ull)};
  // steady_clock is CLOCK_MONOTONIC on Linux; retry when a signal interrupts the sleep.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
  while (nowNs() < deadline) {
  }
}

// Groups with periods up to 2 ms (haptic rates) poll the last 200 µs before
// each deadline: 20% of a core at 1 kHz, bought for sub-microsecond wake-ups.
// With 100 µs, about 1% of the sleeps on this kind of machine still overshot
// the deadline by tens of microseconds (docs/results.md).
// At 4 kHz and more, a quarter of the period: a real-time thread that never
// sleeps is stopped by the kernel for 50 ms of every second
// (sched_rt_runtime_us).
uint64_t spinMarginNs(double periodS) {
  return periodS <= 0.002 ? std::min<uint64_t>(200'000, static_cast<uint64_t>(periodS * 0.25e9)) : 0;
}

constexpr uint64_t kStopCheckNs = 50'000'000;

// Asks for a real-time priority for the fastest group; refused without privileges, which is fine.
bool tryRealtimePriority(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
}

}  // namespace

Scheduler::Scheduler(const std::vector<Component*>& components, const RunPlan& plan, EventLog* events)
    : m_plan(plan), m_events(events) {
  std::map<std::pair<double, std::string>, size_t> byRate;
  for (Component* c : components) {
    const double rate = c->rateHz();
    if (rate <= 0) continue;
    auto [it, inserted] = byRate.emplace(std::make_pair(rate, c->rateGroup()), m_groups.size());
    if (inserted) {
      RateGroup g;
      g.rateHz = rate;
      g.name = c->rateGroup();
      g.periodS = 1.0 / rate;
      g.plannedCalls = plan.callsAt(rate);
      m_groups.push_back(std::move(g));
    }
    GroupMember member;
    member.component = c;
    m_groups[it->second].members.push_back(std::move(member));
  }
  // Highest rate first; at one rate the rate's own group, then the named ones by name (virtual time's tie order).
  std::sort(m_groups.begin(), m_groups.end(), [](const RateGroup& a, const RateGroup& b) {
    return a.rateHz != b.rateHz ? a.rateHz > b.rateHz : a.name < b.name;
  });
  // The first member that paces its group, if any (FramePacer.h).
  for (RateGroup& g : m_groups)
    for (GroupMember& m : g.members)
      if (auto* pacer = dynamic_cast<FramePacer*>(m.component); pacer && pacer->pacesFrames() && !g.pacer)
        g.pacer = pacer;
  // The members that query or respond to contact targets join their group's frame.
  for (RateGroup& g : m_groups) {
    for (GroupMember& m : g.members)
      if (auto* member = dynamic_cast<ContactFrameMember*>(m.component)) member->joinContactFrame(g.contacts);
    g.contacts.seal();
  }
  // Indexed by tick; a tick skipped in real time stays NaN and is left out of timings.csv.
  for (RateGroup& g : m_groups)
    for (GroupMember& m : g.members) m.callUs.assign(g.plannedCalls, std::numeric_limits<float>::quiet_NaN());
}

const RateGroup* Scheduler::group(double rateHz) const {
  for (const RateGroup& g : m_groups)
    if (g.rateHz == rateHz && g.name.empty()) return &g;
  return nullptr;
}

void Scheduler::run(const std::atomic<bool>& stop) {
  if (m_plan.realtime) {
    runRealtime(stop);
  } else {
    runVirtual(stop);
  }
}

uint64_t Scheduler::step(RateGroup& group, uint64_t k) {
  const TickContext context{static_cast<double>(k) / group.rateHz, group.periodS, k, m_events, &group.contacts};
  const uint64_t periodNs = static_cast<uint64_t>(group.periodS * 1e9);
  ++group.calls;  // counted when it starts: a step that throws is still a step taken
  group.currentT = context.t;
  const uint64_t start = nowNs();
  uint64_t before = start;
  group.contacts.begin(context.t);
  for (GroupMember& member : group.members) {
    group.current = &member;  // names the component if its tick throws
    member.component->tick(context);
    const uint64_t after = nowNs();
    const uint64_t ns = after - before;
    member.histogram.record(ns);
    if (k < member.callUs.size()) member.callUs[k] = static_cast<float>(ns * 1e-3);
    ++member.calls;
    if (ns > periodNs) ++member.overruns;
    before = after;
  }
  group.current = nullptr;  // the targets' responses belong to no member
  group.contacts.end();
  const uint64_t total = nowNs() - start;
  group.stepHistogram.record(total);
  return total;
}

std::string Scheduler::describeFailure(const RateGroup& group, const char* what) {
  const Component* culprit = group.current ? group.current->component : nullptr;
  if (m_events) m_events->log(group.currentT, "tick_failed", "", culprit);
  return (culprit ? culprit->path() + ": " : std::string()) + what;
}

void Scheduler::runVirtual(const std::atomic<bool>& stop) {
  std::vector<uint64_t> next(m_groups.size(), 0);
  // The groups by the time of their next call, earliest on top; ties go to
  // the higher rate (earlier in m_groups). A heap: with thousands of groups
  // each step costs their logarithm, not their number.
  struct Due {
    double t;
    size_t group;
  };
  const auto later = [](const Due& a, const Due& b) { return a.t > b.t || (a.t == b.t && a.group > b.group); };
  std::vector<Due> queue;
  queue.reserve(m_groups.size());
  for (size_t i = 0; i < m_groups.size(); ++i)
    if (m_groups[i].plannedCalls > 0) queue.push_back({0.0, i});
  std::make_heap(queue.begin(), queue.end(), later);
  RateGroup* running = nullptr;
  try {
    while (!stop.load(std::memory_order_relaxed)) {
      if (queue.empty()) {
        m_completed = true;
        break;
      }
      std::pop_heap(queue.begin(), queue.end(), later);
      const size_t chosen = queue.back().group;
      queue.pop_back();
      RateGroup& g = m_groups[chosen];
      running = &g;
      const uint64_t ns = step(g, next[chosen]);
      if (ns > static_cast<uint64_t>(g.periodS * 1e9)) ++g.deadlineMisses;  // would miss in real time
      ++next[chosen];
      m_simulatedTime = std::max(m_simulatedTime, static_cast<double>(next[chosen]) / g.rateHz);
      m_progress.store(m_simulatedTime, std::memory_order_relaxed);
      if (next[chosen] < g.plannedCalls) {
        queue.push_back({static_cast<double>(next[chosen]) / g.rateHz, chosen});  // within the reserved size
        std::push_heap(queue.begin(), queue.end(), later);
      }
    }
  } catch (const std::exception& e) {
    m_failure = running ? describeFailure(*running, e.what()) : std::string(e.what());
  } catch (...) {
    m_failure = running ? describeFailure(*running, "unknown exception") : std::string("unknown exception");
  }
  if (m_groups.empty()) {
    m_completed = !stop.load();
    m_simulatedTime = m_completed ? m_plan.duration : 0;
  }
  if (m_completed) m_simulatedTime = m_plan.duration;
  m_progress.store(m_simulatedTime, std::memory_order_relaxed);
}

void Scheduler::stepPaced(RateGroup& g, uint64_t k, uint64_t t0, const std::atomic<bool>& stop) {
  const double periodNs = g.periodS * 1e9;
  // The first frame at the common start; then within [3/4, 3/2] of a period
  // after the last start, as soon as the pacer's input has come.
  // With no input for two frames running (no device, or it stopped), the
  // clock paces the group, so that simulated time keeps up with the wall.
  const double bound = g.unpacedRun >= 2 ? 1.0 : 1.5;
  const uint64_t earliest = k == 0 ? t0 : g.lastStartNs + static_cast<uint64_t>(0.75 * periodNs);
  const uint64_t latest = k == 0 ? t0 : g.lastStartNs + static_cast<uint64_t>(bound * periodNs);
  // Sleeps to 200 µs before the earliest start, then polls. Polling the whole
  // wait would spare the wake-up (a thread that sleeps wakes on a virtual
  // machine into a stall of 100 to 200 µs in about 1% of its frames), but a
  // real-time thread that never sleeps is stopped by the kernel for 50 ms
  // of every second (sched_rt_runtime_us): docs/results.md.
  sleepUntilNs(earliest, spinMarginNs(g.periodS));
  bool input = g.pacer->frameInputWaiting();
  while (!input && nowNs() < latest && !stop.load(std::memory_order_relaxed)) {
    sched_yield();
    input = g.pacer->frameInputWaiting();
  }
  if (input) {
    ++g.pacedFrames;
    g.unpacedRun = 0;
  } else {
    ++g.unpacedFrames;
    ++g.unpacedRun;
  }
  const uint64_t start = nowNs();
  if (g.calls == 0) g.firstStartNs = start;
  g.lastStartNs = start;
  step(g, k);
  if (static_cast<double>(nowNs() - start) > periodNs) ++g.deadlineMisses;
}

void Scheduler::runRealtime(const std::atomic<bool>& stop) {
  std::mutex failureMutex;  // taken only on the failure path, never per tick
  std::atomic<bool> abort{false};
  const uint64_t t0 = nowNs() + 2'000'000;  // start every group together, 2 ms from now
  std::vector<std::thread> threads;
  for (size_t i = 0; i < m_groups.size(); ++i) {
    threads.emplace_back([&, i] {
      RateGroup& g = m_groups[i];
      // Wake as close to each deadline as the kernel allows: no timer slack
      // (50 µs by default for normal threads), and real-time priority for the fastest group.
      prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
      if (i == 0) g.realtimePriority = tryRealtimePriority(80);
      const double periodNs = g.periodS * 1e9;
      const uint64_t spin = spinMarginNs(g.periodS);
      uint64_t k = 0;
      try {
        while (k < g.plannedCalls && !stop.load(std::memory_order_relaxed) && !abort.load(std::memory_order_relaxed)) {
          if (g.pacer) {
            stepPaced(g, k, t0, stop);
            if (i == 0) m_progress.store(static_cast<double>(k + 1) / g.rateHz, std::memory_order_relaxed);
            ++k;
            continue;
          }
          const uint64_t deadline = t0 + static_cast<uint64_t>(static_cast<double>(k) * periodNs);
          // Slow groups sleep in slices so that a stop request is seen within 50 ms.
          while (deadline > nowNs() + kStopCheckNs && !stop.load(std::memory_order_relaxed) &&
                 !abort.load(std::memory_order_relaxed))
            sleepUntilNs(nowNs() + kStopCheckNs, 0);
          sleepUntilNs(deadline, spin);
          const uint64_t wake = nowNs();
          g.wakeLateness.record(wake > deadline ? wake - deadline : 0);
          if (g.calls == 0) g.firstStartNs = wake;
          g.lastStartNs = wake;
          step(g, k);
          if (i == 0) m_progress.store(static_cast<double>(k + 1) / g.rateHz, std::memory_order_relaxed);
          const uint64_t end = nowNs();
          if (static_cast<double>(end - deadline) > periodNs) ++g.deadlineMisses;
          // After a stall, resume at the tick now due instead of bursting through the missed ones.
          const uint64_t due = static_cast<uint64_t>(static_cast<double>(end - t0) / periodNs);
          if (due > k + 1) {
            g.skippedTicks += due - (k + 1);
            g.deadlineMisses += due - (k + 1);
            k = due;
          } else {
            ++k;
          }
        }
      } catch (const std::exception& e) {
        std::lock_guard lock(failureMutex);
        if (!m_failure) m_failure = describeFailure(g, e.what());
        abort = true;
      } catch (...) {
        std::lock_guard lock(failureMutex);
        if (!m_failure) m_failure = describeFailure(g, "unknown exception");
        abort = true;
      }
      g.wallSeconds = static_cast<double>(nowNs() - t0) * 1e-9;
    });
  }
  for (auto& t : threads) t.join();
  m_completed = !stop.load() && !m_failure;
  double elapsed = 0;
  for (const RateGroup& g : m_groups) elapsed = std::max(elapsed, g.wallSeconds);
  m_simulatedTime = m_completed ? m_plan.duration : std::min(elapsed, m_plan.duration);
  m_progress.store(m_simulatedTime, std::memory_order_relaxed);
}

}  // namespace trephine
