#pragma once
// A haptic device driven from outside the process through the device bridge
// (a device program's servo loop, or the emulator): each haptic frame takes
// the newest valid pose that came and sends back the force computed from
// it, never waiting on either. In real time the device paces the haptic
// frames (FramePacer): a frame starts when its pose comes, so the force goes
// back within the device's own frame.
//
// Safety: when no new valid pose has come for `timeout`, the force sent
// ramps to zero over `rampTime` and a bridge_watchdog event is logged; the
// pose is held. Once poses come again the force ramps back, and the first
// new pose is taken wherever the hand is now. The force sent is limited to
// `maxForce`; a NaN is never sent. Foreign, malformed, stale and flooding
// packets are dropped and counted (summary.json).
#include <memory>

#include "framework/core/FramePacer.h"
#include "framework/devices/HapticDevice.h"
#include "framework/runtime/TimingHistogram.h"
#include "plugins/device_bridge/BridgeConnection.h"
#include "plugins/device_bridge/BridgeReceiver.h"
#include "plugins/device_bridge/MonotonicClock.h"
#include "trephine_bridge_watchdog.h"

namespace trephine::device_bridge {

class BridgeDevice final : public HapticDevice, public FramePacer {
 public:
  static constexpr std::string_view kTypeName = "BridgeDevice";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void applyForce(const Vec3& force_N) override;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void reportFacts(std::vector<Fact>& facts) const override;

  bool outsideTheProcess() const override { return true; }
  bool pacesFrames() const override { return d_pace.value(); }
  // Only a valid pose of the device's session paces a frame: junk is read
  // and counted here (a batch a poll), never taken for input.
  bool frameInputWaiting() override { return m_transport && m_receiver.poll(*m_transport, monotonicNs()); }

  // The force last sent to the device (N), after the watchdog and the limit.
  const Vec3& sentForce() const { return m_sentForce; }
  uint64_t watchdogTrips() const { return m_watchdog.trips; }

 protected:
  DeviceSample readSample(double t) override;
  bool connected() const override { return m_connected; }

 private:
  BridgeConnectionFields d_connection{this, BridgeSide::Simulation};
  Field<bool> d_pace{this,
                     "pace",
                     true,
                     {.help = "In real time, start each haptic frame when the device's pose comes, not at the "
                              "clock's deadline (the scene's rate should then be the device's)"}};

  Field<Vec3> d_offset{this,
                       "offset",
                       Vec3::Zero(),
                       {.help = "Added to every position the device sends: where the device's origin lies in the "
                                "scene (a device's origin is the middle of its workspace)",
                        .unit = "mm"}};

  // Whether the device takes this run's forces (the session and last force
  // sequence its poses say it took); notes when it stops and starts again.
  void checkForcesHeard(const trephine_bridge_pose& pose, uint64_t now, double t);

  std::unique_ptr<BridgeTransport> m_transport;
  bool m_transportFailed = false;
  uint64_t m_session = 0;  // this run's, in every force it sends
  BridgeReceiver<trephine_bridge_pose> m_receiver{trephine_bridge_decode_pose};
  trephine_bridge_watchdog m_watchdog{};
  trephine_bridge_pose m_latest{};
  bool m_connected = false;
  bool m_newPose = false;         // a new pose came this frame
  uint64_t m_latestArrivalNs = 0;  // when it was taken
  Vec3 m_sentForce = Vec3::Zero();
  uint64_t m_forceSequence = 0;
  uint64_t m_forcesSent = 0, m_sendFailures = 0, m_forcesLimited = 0, m_framesBeforeDevice = 0;
  uint64_t m_unansweredPoses = 0;    // the device said the force for its previous pose came too late
  uint64_t m_deviceRestarts = 0;     // device programs started again on the channel (new sessions)
  uint64_t m_heardForce = 0;         // the last of this run's force sequences the device said it took
  uint64_t m_heardAtNs = 0;          // when it last moved on (or the first force went)
  bool m_forcesUnheard = false;      // forces go out but the device has not taken one for `timeout`
  uint64_t m_unheardEpisodes = 0, m_unheardFrames = 0;
  TimingHistogram m_deviceRoundTrip;  // as the device measured it (ns)
  TimingHistogram m_poseToForce;      // here, from taking a pose to sending its force (ns)
};

}  // namespace trephine::device_bridge
