// libFuzzer target: arbitrary bytes as what an OpenIGTLink client sends the
// device server (IgtlStreamReader, then the TRANSFORM, STRING and STATUS
// readers). The first byte sets the size of the pieces the stream arrives in.
// Any crash, sanitizer report or hang is a bug; so is a stream read
// differently whole and in pieces, or a TRANSFORM accepted that is not a
// finite rigid transform.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "plugins/openigtlink/IgtlMessages.h"
#include "plugins/openigtlink/IgtlStreamReader.h"

using namespace trephine;
using namespace trephine::openigtlink;

namespace {

struct Outcome {
  std::vector<std::string> messages;
  std::string error;
};

Outcome readStream(const uint8_t* data, size_t size, size_t piece) {
  Outcome outcome;
  IgtlStreamReader reader(
      [](const MessageHeader& h) {
        return h.typeName() == "TRANSFORM" || h.typeName() == "STRING" || h.typeName() == "STATUS";
      },
      [&](const MessageHeader& h, std::span<const unsigned char> content) {
        std::string seen(h.typeName());
        if (h.typeName() == "TRANSFORM") {
          if (const auto t = decodeTransform(content)) {
            if (!t->translation.allFinite() || !t->rotation.allFinite()) __builtin_trap();
            if (std::abs(t->rotation.determinant() - 1.0) > 0.011) __builtin_trap();
            seen += " ok";
          }
        } else if (h.typeName() == "STRING") {
          if (const auto text = decodeString(content)) seen += " " + std::to_string(text->size());
        } else if (const auto subcode = decodeStatusSubcode(content)) {
          seen += " " + std::to_string(*subcode);
        }
        outcome.messages.push_back(seen);
      });
  for (size_t at = 0; at < size && !reader.failed(); at += piece)
    reader.feed({data + at, std::min(piece, size - at)});
  outcome.error = reader.error();
  return outcome;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const size_t piece = 1 + data[0];
  const Outcome pieces = readStream(data + 1, size - 1, piece);
  const Outcome whole = readStream(data + 1, size - 1, size);
  if (pieces.messages != whole.messages || pieces.error != whole.error) __builtin_trap();
  return 0;
}
