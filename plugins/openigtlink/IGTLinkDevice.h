#pragma once
// A haptic device whose pose comes over OpenIGTLink (a tracker, a robot, 3D
// Slicer, PLUS) and which sends the force back (the brief's contract):
//
//   <IGTLinkDevice name="device" port="18944" transformName="Tool" forceName="Force" rate="1000"/>
//
// An OpenIGTLink server on 127.0.0.1:port (`host` binds elsewhere, on
// request only). It takes TRANSFORM messages named `transformName`: the
// translation (mm) is the device point, the rotation its orientation. In
// every haptic frame after a pose has arrived it sends each connected client
// a SENSOR named `forceName` with three float64 values: the force on the
// device in newtons, in the same frame. Buttons come as STRING (the mask as a
// decimal number) or STATUS (its subcode) messages named `buttonsName`.
//
// One client drives it: by default the first whose pose is taken (until it
// disconnects; then the next), or the one `client` names. Other clients'
// TRANSFORMs are counted and ignored, and so is a pose beyond `workspace`
// from the origin, so a stray first pose cannot become the hand's place.
//
// The network lives in the server's thread (IgtlServer); the haptic loop
// takes the newest pose from a triple buffer and posts the force to a ring.
#include <memory>

#include "framework/devices/HapticDevice.h"
#include "plugins/openigtlink/IgtlServer.h"
#include "plugins/openigtlink/IgtlServerFields.h"

namespace trephine::openigtlink {

class IGTLinkDevice final : public HapticDevice {
 public:
  static constexpr std::string_view kTypeName = "IGTLinkDevice";

  void init(InitContext& context) override;
  void prepare(const RunPlan& plan) override;
  void applyForce(const Vec3& force_N) override;
  void finish(FinishContext& context) override;
  void reportCounters(std::vector<Counter>& counters) const override;
  void reportFacts(std::vector<Fact>& facts) const override;
  bool outsideTheProcess() const override { return true; }

  // The port it listens on (the one asked for, or the one given for port 0); 0 before prepare, and in
  // virtual time (the server starts only in real time).
  uint16_t listeningPort() const { return m_server ? m_server->port() : 0; }
  // Stops serving (as at the end of a run): clients are disconnected, the counters stay.
  void stopServing() {
    if (m_server) m_server->stop();
  }

 protected:
  DeviceSample readSample(double t) override;
  bool connected() const override { return m_connected; }
  bool fromRas() const { return d_frame.value() == "RAS"; }

 private:
  IgtlServerFields d_server{
      this, 18944, "TCP port of the OpenIGTLink server (18944: the protocol's usual one; 0: any free one)"};
  Field<std::string> d_transformName{
      this, "transformName", "Tool", {.help = "Device name of the TRANSFORM messages that carry the pose"}};
  Field<std::string> d_forceName{
      this, "forceName", "Force", {.help = "Device name of the SENSOR messages that carry the force back"}};
  Field<std::string> d_buttonsName{
      this,
      "buttonsName",
      "",
      {.help = "Device name of STRING (a decimal mask) or STATUS (its subcode) messages that set the buttons; "
               "empty: none"}};

  Field<std::string> d_client{
      this,
      "client",
      "",
      {.help = "The one client whose poses drive the device, as HOST or HOST:PORT (a dotted IPv4 address); empty: "
               "the first client whose pose is taken, until it disconnects"}};
  Field<double> d_workspace{this,
                            "workspace",
                            1000.0,
                            {.help = "A pose farther than this from the origin is ignored (never taken as the "
                                     "hand's place, first or later)",
                             .unit = "mm",
                             .min = 1.0}};

  EnumField d_frame{this,
                    "frame",
                    {"device", "RAS"},
                    "device",
                    {.help = "The frame of the TRANSFORMs that come: device (the device's or tracker's own, taken as "
                             "they are) or RAS (3D Slicer's patient frame: turned into the scene's LPS, the force "
                             "sent back in RAS)"}};

  std::unique_ptr<IgtlServer> m_server;
  ReceivedPose m_pose;
  bool m_connected = false;
  double m_t = 0;  // s, the frame's time, for the SENSOR's stamp
};

}  // namespace trephine::openigtlink
