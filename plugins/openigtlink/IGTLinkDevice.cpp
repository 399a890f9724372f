#include "plugins/openigtlink/IGTLinkDevice.h"

#include <arpa/inet.h>

#include "framework/core/Lifecycle.h"

namespace trephine::openigtlink {

void IGTLinkDevice::init(InitContext& context) {
  if (const std::string problem = d_server.hostProblem(); !problem.empty()) context.error(d_server.host, problem);
  for (const Field<std::string>* name : {&d_transformName, &d_forceName, &d_buttonsName}) {
    const std::string& text = name->value();
    if (text.size() > kDeviceNameSize)
      context.error(*name, "'" + text + "' is longer than OpenIGTLink's 20-byte device names");
    for (const char c : text)
      if (c < 0x20 || c > 0x7e) context.error(*name, "a device name is printable ASCII");
  }
  if (d_transformName.value().empty()) context.error(d_transformName, "the TRANSFORM's device name is needed");
  if (const std::string& client = d_client.value(); !client.empty()) {
    const size_t colon = client.find(':');
    in_addr parsed{};
    const std::string host = client.substr(0, colon);
    const std::string port = colon == std::string::npos ? "1" : client.substr(colon + 1);
    const bool portOk = !port.empty() && port.size() <= 5 &&
                        port.find_first_not_of("0123456789") == std::string::npos && std::stoi(port) >= 1 &&
                        std::stoi(port) <= 65535;
    if (inet_pton(AF_INET, host.c_str(), &parsed) != 1 || !portOk)
      context.error(d_client, "'" + client + "' is not HOST or HOST:PORT (a dotted IPv4 address and a port from 1 "
                              "to 65535)");
  }
  if (d_forceName.value().empty()) context.error(d_forceName, "the SENSOR's device name is needed");
}

void IGTLinkDevice::prepare(const RunPlan& plan) {
  HapticDevice::prepare(plan);
  IgtlServerOptions options;
  options.host = d_server.host.value();
  options.port = d_server.portNumber();
  options.maxClients = static_cast<size_t>(d_server.maxClients.value());
  options.transformName = d_transformName.value();
  options.forceName = d_forceName.value();
  options.buttonsName = d_buttonsName.value();
  options.client = d_client.value();
  options.workspace = d_workspace.value();
  options.clientTimeout = d_server.clientTimeout.value();
  // In virtual time (validate, a run without --realtime) no server: the load warned.
  if (plan.realtime) m_server = std::make_unique<IgtlServer>(options);  // throws, naming the address
}

DeviceSample IGTLinkDevice::readSample(double t) {
  m_t = t;
  if (!m_server) return DeviceSample{t};
  TripleBuffer<ReceivedPose>& poses = m_server->poses();
  if (poses.fetch()) {
    m_pose = poses.read();
    m_connected = m_pose.sequence > 0;
  }
  DeviceSample sample;
  sample.t = t;
  sample.position = m_pose.transform.translation;
  sample.orientation = Quat(m_pose.transform.rotation);
  if (fromRas()) {
    // RAS to the scene's LPS: x and y negated, the rotation seen from LPS axes (F R F).
    const Eigen::Matrix3d flip = Vec3(-1, -1, 1).asDiagonal();
    sample.position = flip * sample.position;
    sample.orientation = Quat(flip * m_pose.transform.rotation * flip);
  }
  sample.buttons = m_pose.buttons;
  return sample;
}

void IGTLinkDevice::applyForce(const Vec3& force_N) {
  HapticDevice::applyForce(force_N);
  // In every frame after a pose has arrived (the contract); a force that is
  // not finite goes as zero.
  const Vec3 sent = fromRas() ? Vec3(-force_N.x(), -force_N.y(), force_N.z()) : force_N;  // back in its frame
  if (m_connected && m_server) m_server->postForce(sent.allFinite() ? sent : Vec3::Zero(), m_t);
}

void IGTLinkDevice::finish(FinishContext& context) {
  if (m_server) m_server->stop();  // stops serving before the files are written; the counters stay
  HapticDevice::finish(context);
}

void IGTLinkDevice::reportCounters(std::vector<Counter>& counters) const {
  HapticDevice::reportCounters(counters);
  if (!m_server) return;
  const ServerCounters& c = m_server->counters();
  const auto add = [&](const char* name, uint64_t value) {
    counters.push_back({name, static_cast<double>(value)});
  };
  add("transforms_received", c.transforms);
  add("bad_transforms", c.badTransforms);
  add("button_messages", c.buttonMessages);
  add("other_messages", c.otherMessages);
  add("clients_accepted", c.clientsAccepted);
  add("clients_refused", c.clientsRefused);
  add("clients_broken", c.clientsBroken);
  add("clients_slow", c.clientsSlow);
  add("clients_stalled", c.clientsStalled);
  add("clients_idle", c.clientsIdle);
  add("poses_other_clients", c.posesOtherClients);
  add("poses_outside_workspace", c.posesOutsideWorkspace);
  add("sensors_sent", c.sensorsSent);
  add("sensors_dropped", c.sensorsDropped);
  add("forces_dropped", m_server->forcesDropped());
}

void IGTLinkDevice::reportFacts(std::vector<Fact>& facts) const {
  if (m_server) facts.push_back({"listening", d_server.host.value() + ":" + std::to_string(m_server->port())});
}

}  // namespace trephine::openigtlink
