#include "plugins/openigtlink/IgtlServerFields.h"

#include <arpa/inet.h>

namespace trephine::openigtlink {

std::string IgtlServerFields::hostProblem() const {
  in_addr parsed{};
  if (inet_pton(AF_INET, host.value().c_str(), &parsed) == 1) return {};
  return "'" + host.value() + "' is not a dotted IPv4 address (names are not looked up)";
}

}  // namespace trephine::openigtlink
