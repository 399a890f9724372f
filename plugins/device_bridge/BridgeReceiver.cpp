#include "plugins/device_bridge/BridgeReceiver.h"

#include <string>

namespace trephine::device_bridge {

void ReceiveCounters::count(trephine_bridge_status status) {
  switch (status) {
    case TREPHINE_BRIDGE_OK: break;
    case TREPHINE_BRIDGE_WRONG_SIZE: ++wrongSize; break;
    case TREPHINE_BRIDGE_BAD_MAGIC: ++badMagic; break;
    case TREPHINE_BRIDGE_BAD_VERSION: ++badVersion; break;
    case TREPHINE_BRIDGE_BAD_KIND: ++badKind; break;
    default: ++badValues; break;
  }
}

void ReceiveCounters::report(std::vector<Counter>& counters, const char* prefix) const {
  const std::string p = prefix;
  const auto add = [&](const char* name, uint64_t value) {
    counters.push_back({p + name, static_cast<double>(value)});
  };
  add("received", received);
  add("foreign", foreign);
  add("malformed", malformed());
  add("malformed_size", wrongSize);
  add("malformed_magic", badMagic);
  add("wrong_version", badVersion);
  add("wrong_kind", badKind);
  add("bad_values", badValues);
  add("stale", stale);
  add("too_far_ahead", tooFarAhead);
  add("other_session", otherSession);
  add("lost", lost);
  add("superseded", superseded);
  add("flood_ticks", floods);
  add("sessions", sessions);
}

}  // namespace trephine::device_bridge
