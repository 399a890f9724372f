#include "plugins/device_bridge/BridgeDeviceSide.h"

#include <algorithm>
#include <limits>

#include "framework/core/AtomicFile.h"
#include "framework/core/Lifecycle.h"
#include "framework/logs/EventLog.h"
#include "plugins/device_bridge/MonotonicClock.h"

namespace trephine::device_bridge {

void BridgeDeviceSide::init(InitContext& context) {
  if (const std::string problem = d_connection.problem(); !problem.empty()) context.error(*this, problem);
}

void BridgeDeviceSide::prepare(const RunPlan& plan) {
  Component::prepare(plan);
  m_frames.assign(d_record.value() ? plan.callsAt(rateHz()) : 0, Frame{});
  m_frameCount = 0;
  trephine_bridge_watchdog_init(&m_watchdog, d_connection.timeout.value(), d_connection.rampTime.value());
  // A session of this run's own: a simulation that kept running takes this
  // side's poses from their new start once the earlier session went quiet.
  m_receiver.reset(d_connection.timeout.value());
  m_session = trephine_bridge_new_session();
  m_poseSequence = 0;
  m_posesSent = 0;
  m_heard = false;
  // In virtual time the device side sends nothing: the simulation it talks to runs in wall time.
  m_transport.reset();
  if (plan.realtime) m_transport = d_connection.open();
}

void BridgeDeviceSide::takeForces(uint64_t now, const TickContext& context) {
  const std::optional<trephine_bridge_force> force = m_receiver.takeNewest(*m_transport, now);
  if (!force) return;
  // A simulation started again on the channel: its forces count from its new start.
  if (m_receiver.takeRestart() && context.events)
    context.events->log(context.t, "bridge_simulation_restarted", "", this);
  trephine_bridge_watchdog_heard(&m_watchdog, now);
  m_heard = true;
  m_latest = *force;
  if (force->flags & TREPHINE_BRIDGE_FORCE_WATCHDOG) ++m_simulationWatchdogForces;
  if (!m_answered && force->answered_sequence == m_poseSequence && m_posesSent > 0) {
    m_answered = true;
    const uint64_t roundTrip = now - m_sentAtNs;
    m_roundTrip.record(roundTrip);
    m_lastRoundTripNs = static_cast<uint32_t>(std::min<uint64_t>(roundTrip, std::numeric_limits<uint32_t>::max()));
  }
}

void BridgeDeviceSide::tick(const TickContext& context) {
  if (!m_transport) return;
  HapticDevice& device = *l_device;
  const DeviceState& state = device.state();
  uint64_t now = monotonicNs();
  takeForces(now, context);  // what came since the last frame (a late answer)
  if (state.valid) {
    trephine_bridge_pose pose{};
    pose.sequence = m_poseSequence + 1;
    pose.device_time_ns = now;
    for (int i = 0; i < 3; ++i) pose.position_mm[i] = state.pose.position[i];
    const Quat& q = state.pose.orientation;
    pose.orientation_wxyz[0] = q.w();
    pose.orientation_wxyz[1] = q.x();
    pose.orientation_wxyz[2] = q.y();
    pose.orientation_wxyz[3] = q.z();
    pose.buttons = state.buttons;
    pose.session = m_session;
    // Which of the simulation's forces this side takes: so it knows it is heard.
    pose.heard_session = m_receiver.stream().session;
    pose.heard_sequence = m_receiver.stream().sequence;
    pose.round_trip_ns = m_answered ? m_lastRoundTripNs : 0;
    if (m_posesSent > 0) {
      if (m_answered) {
        ++m_answeredInFrame;
      } else {
        ++m_lateAnswers;
      }
    }
    unsigned char bytes[TREPHINE_BRIDGE_POSE_SIZE];
    if (trephine_bridge_encode_pose(&pose, bytes) == TREPHINE_BRIDGE_OK && m_transport->send(bytes, sizeof bytes)) {
      m_poseSequence = pose.sequence;
      m_sentAtNs = now;
      m_answered = false;
      ++m_posesSent;
      // Poll for the answer, as a servo loop that sends first and commands last.
      // At most half the frame: the rest is the hand's and the clock's.
      const double wait = std::min(d_awaitAnswer.value(), 0.5 / rateHz());
      const uint64_t until = now + static_cast<uint64_t>(wait * 1e9);
      while (!m_answered && now < until) {
        if (m_transport->waiting()) takeForces(now = monotonicNs(), context);
        now = monotonicNs();
      }
    } else {
      ++m_sendFailures;
    }
  }
  int trippedNow = 0;
  trephine_bridge_watchdog_update(&m_watchdog, now, &trippedNow);
  if (trippedNow && context.events)
    context.events->log(context.t, "bridge_watchdog", "tripped", this,
                        static_cast<double>(now - m_watchdog.last_heard_ns) * 1e-6);
  double commanded[3] = {0, 0, 0};
  if (m_heard &&
      trephine_bridge_guard_force(&m_watchdog, m_latest.force_n, d_connection.maxForce.value(), commanded))
    ++m_forcesLimited;
  m_commanded = Vec3(commanded[0], commanded[1], commanded[2]);
  device.applyForce(m_commanded);
  if (m_frameCount < m_frames.size())
    m_frames[m_frameCount++] = {context.t,
                                m_answered ? m_lastRoundTripNs * 1e-3 : std::numeric_limits<double>::quiet_NaN(),
                                m_commanded, m_watchdog.gain};
}

void BridgeDeviceSide::finish(FinishContext& context) {
  if (!d_record.value() || context.outputDirectory().empty()) return;
  const std::string name = FinishContext::defaultFileName("bridge", *this);
  if (!context.claimOutput(*this, name)) return;
  try {
    writeFileAtomically(context.outputDirectory() / name, [&](std::ostream& out) {
      out << "t,round_trip_us,fx,fy,fz,gain\n";
      out.precision(9);
      for (size_t i = 0; i < m_frameCount; ++i) {
        const Frame& f = m_frames[i];
        out << f.t << ',';
        if (f.roundTripUs == f.roundTripUs) out << f.roundTripUs;
        out << ',' << f.force.x() << ',' << f.force.y() << ',' << f.force.z() << ',' << f.gain << '\n';
      }
    });
  } catch (const FileWriteError& e) {
    context.error(*this, e.what());
  }
}

void BridgeDeviceSide::declareOutputs(std::vector<OutputFile>& outputs) const {
  if (d_record.value()) outputs.push_back({FinishContext::defaultFileName("bridge", *this), &d_record});
}

void BridgeDeviceSide::reportCounters(std::vector<Counter>& counters) const {
  m_receiver.counters().report(counters, "forces_");
  const auto add = [&](const char* name, double value) { counters.push_back({name, value}); };
  add("poses_sent", static_cast<double>(m_posesSent));
  add("send_failures", static_cast<double>(m_sendFailures));
  add("answered_in_frame", static_cast<double>(m_answeredInFrame));
  add("late_answers", static_cast<double>(m_lateAnswers));
  add("forces_limited", static_cast<double>(m_forcesLimited));
  add("watchdog_trips", static_cast<double>(m_watchdog.trips));
  add("simulation_watchdog_forces", static_cast<double>(m_simulationWatchdogForces));
  const TimingSummary rt = m_roundTrip.summary();
  add("round_trips_measured", static_cast<double>(rt.count));
  add("round_trip_p50_us", rt.p50);
  add("round_trip_p99_us", rt.p99);
  add("round_trip_max_us", rt.max);
}

void BridgeDeviceSide::reportFacts(std::vector<Fact>& facts) const {
  if (m_transport) facts.push_back({"transport", m_transport->describe()});
}

}  // namespace trephine::device_bridge
