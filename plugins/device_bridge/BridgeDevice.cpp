#include "plugins/device_bridge/BridgeDevice.h"

#include <stdexcept>

#include "framework/core/Lifecycle.h"
#include "framework/logs/EventLog.h"
#include "plugins/device_bridge/MonotonicClock.h"

namespace trephine::device_bridge {

void BridgeDevice::init(InitContext& context) {
  if (const std::string problem = d_connection.problem(); !problem.empty()) context.error(*this, problem);
}

void BridgeDevice::prepare(const RunPlan& plan) {
  HapticDevice::prepare(plan);
  trephine_bridge_watchdog_init(&m_watchdog, d_connection.timeout.value(), d_connection.rampTime.value());
  // A session of this run's own, its forces numbered from 1 in it: a device
  // program that kept running takes them once the earlier run went quiet.
  m_receiver.reset(d_connection.timeout.value());
  m_session = trephine_bridge_new_session();
  m_forceSequence = 0;
  m_heardForce = m_heardAtNs = 0;
  m_forcesUnheard = m_transportFailed = false;
  // In virtual time (validate, a run without --realtime) nothing is opened: the load warned.
  if (plan.realtime) m_transport = d_connection.open();  // throws, naming what failed
}

DeviceSample BridgeDevice::readSample(double t) {
  const uint64_t now = monotonicNs();
  if (!m_transport) {
    ++m_framesBeforeDevice;
    return DeviceSample{t};
  }
  if (const char* failure = m_transport->failure(); failure && !m_transportFailed) {
    m_transportFailed = true;  // no pose comes from now: the watchdog takes the force to zero
    if (EventLog* events = tickEvents()) events->log(t, "bridge_lost", failure, this);
  }
  trephine_bridge_address from{};
  const std::optional<trephine_bridge_pose> pose = m_receiver.takeNewest(*m_transport, now, &from);
  m_newPose = pose.has_value();
  if (pose) {
    m_transport->followPeer(from);
    const bool restarted = m_receiver.takeRestart();
    if (restarted) {
      // A device program started again: its hand is where it is now.
      ++m_deviceRestarts;
      forgetLastSample();
      if (EventLog* events = tickEvents()) events->log(t, "bridge_device_restarted", "", this);
    }
    const bool wasQuiet = m_watchdog.tripped;
    // A device program that starts again, or comes back after a quiet spell,
    // has its timeout to take this run's forces from now.
    if (restarted || wasQuiet) m_heardAtNs = now;
    checkForcesHeard(*pose, now, t);
    trephine_bridge_watchdog_heard(&m_watchdog, now);
    // What the device measured for its previous pose: the round trip, or 0
    // when that pose's force came after it sent this one.
    if (pose->round_trip_ns > 0) {
      m_deviceRoundTrip.record(pose->round_trip_ns);
    } else if (m_forcesSent > 0) {
      ++m_unansweredPoses;
    }
    if (wasQuiet) {
      // The hand moved while the device was quiet: take it where it is now.
      forgetLastSample();
      if (EventLog* events = tickEvents()) events->log(t, "bridge_watchdog", "recovered", this);
    }
    m_latest = *pose;
    m_latestArrivalNs = now;
    m_connected = true;
  } else if (!m_connected) {
    ++m_framesBeforeDevice;
  }
  int trippedNow = 0;
  trephine_bridge_watchdog_update(&m_watchdog, now, &trippedNow);
  if (trippedNow)
    if (EventLog* events = tickEvents())
      events->log(t, "bridge_watchdog", "tripped", this, static_cast<double>(now - m_watchdog.last_heard_ns) * 1e-6);

  DeviceSample sample;
  sample.t = t;
  sample.position =
      d_offset.value() + Vec3(m_latest.position_mm[0], m_latest.position_mm[1], m_latest.position_mm[2]);
  sample.orientation =
      Quat(m_latest.orientation_wxyz[0], m_latest.orientation_wxyz[1], m_latest.orientation_wxyz[2],
           m_latest.orientation_wxyz[3]);
  sample.buttons = m_latest.buttons;
  return sample;
}

void BridgeDevice::checkForcesHeard(const trephine_bridge_pose& pose, uint64_t now, double t) {
  if (m_forcesSent == 0) return;
  if (pose.heard_session == m_session && trephine_bridge_is_newer(m_heardForce, pose.heard_sequence)) {
    m_heardForce = pose.heard_sequence;
    m_heardAtNs = now;
    if (m_forcesUnheard) {
      m_forcesUnheard = false;
      if (EventLog* events = tickEvents()) events->log(t, "bridge_forces_unheard", "recovered", this);
    }
    return;
  }
  // The device answers with poses but takes none of this run's forces: it
  // commands something else (another simulation's, or zero).
  const uint64_t timeout = static_cast<uint64_t>(d_connection.timeout.value() * 1e9);
  if (now - m_heardAtNs <= timeout) return;
  ++m_unheardFrames;
  if (m_forcesUnheard) return;
  m_forcesUnheard = true;
  ++m_unheardEpisodes;
  if (EventLog* events = tickEvents())
    events->log(t, "bridge_forces_unheard", "the device takes none of this run's forces", this,
                static_cast<double>(now - m_heardAtNs) * 1e-6);
}

void BridgeDevice::applyForce(const Vec3& force_N) {
  HapticDevice::applyForce(force_N);
  if (!m_connected || !m_transport) return;
  const double wanted[3] = {force_N.x(), force_N.y(), force_N.z()};
  double sent[3];
  const int limited = trephine_bridge_guard_force(&m_watchdog, wanted, d_connection.maxForce.value(), sent);
  if (limited) ++m_forcesLimited;
  m_sentForce = Vec3(sent[0], sent[1], sent[2]);

  trephine_bridge_force packet{};
  packet.sequence = ++m_forceSequence;
  packet.session = m_session;
  packet.answered_sequence = m_latest.sequence;
  packet.answered_device_time_ns = m_latest.device_time_ns;
  for (int i = 0; i < 3; ++i) packet.force_n[i] = sent[i];
  packet.flags = (m_watchdog.gain < 1.0 ? TREPHINE_BRIDGE_FORCE_WATCHDOG : 0u) |
                 (limited ? TREPHINE_BRIDGE_FORCE_CLAMPED : 0u);
  unsigned char bytes[TREPHINE_BRIDGE_FORCE_SIZE];
  const uint64_t now = monotonicNs();
  packet.simulation_time_ns = now;
  // The guard's force is finite and within maxForce (at most 1000 N): it always encodes.
  if (trephine_bridge_encode_force(&packet, bytes) != TREPHINE_BRIDGE_OK || !m_transport->send(bytes, sizeof bytes)) {
    ++m_sendFailures;
    return;
  }
  if (m_forcesSent++ == 0) m_heardAtNs = now;  // the device has its timeout to take the first
  if (m_newPose) m_poseToForce.record(now - m_latestArrivalNs);
}

void BridgeDevice::finish(FinishContext& context) {
  // The run is over: the device is told to let go now, not at its own
  // watchdog's timeout.
  if (m_connected && m_transport) {
    trephine_bridge_force packet{};
    packet.sequence = ++m_forceSequence;
    packet.session = m_session;
    packet.answered_sequence = m_latest.sequence;
    packet.answered_device_time_ns = m_latest.device_time_ns;
    packet.simulation_time_ns = monotonicNs();
    packet.flags = TREPHINE_BRIDGE_FORCE_WATCHDOG;
    unsigned char bytes[TREPHINE_BRIDGE_FORCE_SIZE];
    if (trephine_bridge_encode_force(&packet, bytes) == TREPHINE_BRIDGE_OK) m_transport->send(bytes, sizeof bytes);
  }
  HapticDevice::finish(context);
}

void BridgeDevice::reportCounters(std::vector<Counter>& counters) const {
  HapticDevice::reportCounters(counters);
  m_receiver.counters().report(counters, "poses_");
  const auto add = [&](const char* name, double value) { counters.push_back({name, value}); };
  add("frames_before_device", static_cast<double>(m_framesBeforeDevice));
  add("forces_sent", static_cast<double>(m_forcesSent));
  add("send_failures", static_cast<double>(m_sendFailures));
  add("forces_limited", static_cast<double>(m_forcesLimited));
  add("watchdog_trips", static_cast<double>(m_watchdog.trips));
  // What the device measured: from sending a pose to receiving its force (µs).
  const TimingSummary rt = m_deviceRoundTrip.summary();
  add("round_trips_measured", static_cast<double>(rt.count));
  add("round_trip_p50_us", rt.p50);
  add("round_trip_p99_us", rt.p99);
  add("round_trip_max_us", rt.max);
  add("unanswered_poses", static_cast<double>(m_unansweredPoses));
  add("device_restarts", static_cast<double>(m_deviceRestarts));
  add("forces_unheard_episodes", static_cast<double>(m_unheardEpisodes));
  add("forces_unheard_frames", static_cast<double>(m_unheardFrames));
  add("transport_lost", m_transportFailed ? 1.0 : 0.0);
  const TimingSummary here = m_poseToForce.summary();
  add("pose_to_force_p50_us", here.p50);
  add("pose_to_force_p99_us", here.p99);
  add("pose_to_force_max_us", here.max);
}

void BridgeDevice::reportFacts(std::vector<Fact>& facts) const {
  if (m_transport) facts.push_back({"transport", m_transport->describe()});
}

}  // namespace trephine::device_bridge
