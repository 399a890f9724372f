#pragma once
// Cuts one client's TCP byte stream into OpenIGTLink messages, however the
// bytes arrive (a header split over reads, many messages in one). Bodies of
// the message types the server reads are kept (up to kMaxKeptBody) and
// checked against their CRC; every other message is skipped without being
// kept. A stream that breaks the protocol (a header no client sends, a kept
// body over the limit, a CRC that does not match) is refused for good: the
// server closes that connection. Its buffers are allocated once.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "plugins/openigtlink/IgtlMessages.h"

namespace trephine::openigtlink {

class IgtlStreamReader {
 public:
  static constexpr size_t kMaxKeptBody = 64 * 1024;        // bytes; a TRANSFORM's is 48 (60 + metadata in v2)
  static constexpr uint64_t kMaxSkippedBody = 1ull << 30;  // bytes; an IMAGE from a scanner fits

  // Which message types to keep (and check) rather than skip.
  using Wanted = std::function<bool(const MessageHeader&)>;
  // Called for each kept message whose CRC matched, with its content (versions 2 and 3: without the
  // extended header and the metadata).
  using OnMessage = std::function<void(const MessageHeader&, std::span<const unsigned char> content)>;

  IgtlStreamReader(Wanted wanted, OnMessage onMessage);

  // Feeds bytes as they came. Returns false once the stream broke the
  // protocol (then error() says how); nothing more is read from it.
  bool feed(std::span<const unsigned char> bytes);
  bool failed() const { return !m_error.empty(); }
  // Whether a message has begun and not yet ended (a client that stops
  // here holds its connection without sending anything whole).
  bool midMessage() const { return m_headerFill > 0 || m_inBody; }
  const std::string& error() const { return m_error; }

  uint64_t messagesKept() const { return m_kept; }
  uint64_t messagesSkipped() const { return m_skipped; }

 private:
  Wanted m_wanted;
  OnMessage m_onMessage;
  std::array<unsigned char, kHeaderSize> m_headerBytes{};
  size_t m_headerFill = 0;
  MessageHeader m_header;
  bool m_inBody = false;
  bool m_keeping = false;
  uint64_t m_bodyLeft = 0;
  std::vector<unsigned char> m_body;  // reserved to kMaxKeptBody once
  std::string m_error;
  uint64_t m_kept = 0, m_skipped = 0;
};

}  // namespace trephine::openigtlink
