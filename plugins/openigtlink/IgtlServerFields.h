#pragma once
// The fields of an OpenIGTLink server component (the device and the
// exporter): where it listens and how many clients it serves.
#include <cstdint>
#include <string>

#include "framework/core/Field.h"

namespace trephine::openigtlink {

struct IgtlServerFields {
  IgtlServerFields(FieldOwner* owner, int defaultPort, std::string_view portHelp)
      : port{owner, "port", defaultPort, {.help = portHelp, .min = 0.0, .max = 65535.0}},
        host{owner,
             "host",
             "127.0.0.1",
             {.help = "Address the server binds: loopback unless another (a dotted IPv4 address) is asked for"}},
        maxClients{
            owner, "maxClients", 4, {.help = "Connections served at once; more are refused", .min = 1.0, .max = 64.0}},
        clientTimeout{owner,
                      "clientTimeout",
                      5.0,
                      {.help = "A client that began a message and sent nothing more for this long is let go; so is "
                               "one that has sent no message since it connected this long ago, when every "
                               "connection is taken and another client asks for one",
                       .unit = "s",
                       .min = 0.01,
                       .max = 3600.0}} {}

  // What is wrong with `host`, or "" (names are not looked up).
  std::string hostProblem() const;
  uint16_t portNumber() const { return static_cast<uint16_t>(port.value()); }

  Field<int> port;
  Field<std::string> host;
  Field<int> maxClients;
  Field<double> clientTimeout;
};

}  // namespace trephine::openigtlink
