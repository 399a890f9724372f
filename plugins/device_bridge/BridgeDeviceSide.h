#pragma once
// The device's end of the bridge, as a component: each frame it sends the
// linked device's pose to the simulation, waits up to `awaitAnswer` for the
// force that answers it (as a servo loop that sends first and commands
// last), and commands the device the newest force it has, through its own
// watchdog and force limit. With a HandDevice it is the device emulator: a
// simulated hand on the far side of the process boundary, run with
// `trephine run emulator.xml --realtime` beside the simulation.
//
// Safety on this side: when no new valid force has come for `timeout` (the
// simulation stopped, crashed or hangs), the force commanded ramps to zero
// over `rampTime` and a bridge_watchdog event is logged; forces are limited
// to `maxForce`.
#include <memory>

#include "framework/core/Component.h"
#include "framework/devices/HapticDevice.h"
#include "framework/runtime/TimingHistogram.h"
#include "plugins/device_bridge/BridgeConnection.h"
#include "plugins/device_bridge/BridgeReceiver.h"
#include "trephine_bridge_watchdog.h"

namespace trephine::device_bridge {

class BridgeDeviceSide final : public Component {
 public:
  static constexpr std::string_view kTypeName = "BridgeDeviceSide";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void tick(const TickContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void reportFacts(std::vector<Fact>& facts) const override;
  void finish(FinishContext& context) override;
  void declareOutputs(std::vector<OutputFile>& outputs) const override;

  const Vec3& commandedForce() const { return m_commanded; }

 private:
  // Takes the newest force that came, feeding the watchdog; notes the round
  // trip when it answers the pose just sent.
  void takeForces(uint64_t now, const TickContext& context);

  Link<HapticDevice> l_device{this, "device", {.help = "The device whose poses are sent and which is commanded "
                                                        "the forces that come back", .required = true}};
  RateField d_rate{this, 1000.0, "The device's servo rate"};
  BridgeConnectionFields d_connection{this, BridgeSide::Device};
  Field<double> d_awaitAnswer{this,
                              "awaitAnswer",
                              0.0005,
                              {.help = "After sending a pose, how long to poll for the force that answers it "
                                       "before commanding the newest one at hand (0: do not wait; at most half "
                                       "a period)",
                               .unit = "s",
                               .min = 0.0,
                               .max = 0.1}};

  Field<bool> d_record{this,
                       "record",
                       true,
                       {.help = "Write what this side saw each frame to bridge.<path with / as .>.csv: the round "
                                "trip, the force commanded and the watchdog's gain"}};

  // One frame as this side saw it (the record).
  struct Frame {
    double t = 0;             // s
    double roundTripUs = 0;   // of this frame's pose; NaN when its answer did not come in the frame
    Vec3 force = Vec3::Zero();  // N, commanded
    double gain = 0;          // the watchdog's
  };
  std::vector<Frame> m_frames;  // preallocated in prepare()
  size_t m_frameCount = 0;

  std::unique_ptr<BridgeTransport> m_transport;
  BridgeReceiver<trephine_bridge_force> m_receiver{trephine_bridge_decode_force};
  trephine_bridge_watchdog m_watchdog{};
  trephine_bridge_force m_latest{};
  bool m_heard = false;
  Vec3 m_commanded = Vec3::Zero();
  uint64_t m_poseSequence = 0, m_sentAtNs = 0;
  uint64_t m_session = 0;  // this run's, in every pose it sends
  uint32_t m_lastRoundTripNs = 0;  // of the previous pose; 0 when it was not answered in its frame
  bool m_answered = false;         // the pose just sent was answered
  uint64_t m_posesSent = 0, m_sendFailures = 0, m_answeredInFrame = 0, m_lateAnswers = 0, m_forcesLimited = 0;
  uint64_t m_simulationWatchdogForces = 0;  // forces the simulation flagged as cut by its own watchdog
  TimingHistogram m_roundTrip;              // ns
};

}  // namespace trephine::device_bridge
