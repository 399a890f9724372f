#include "plugins/openigtlink/IgtlStreamReader.h"

#include <algorithm>

namespace trephine::openigtlink {

IgtlStreamReader::IgtlStreamReader(Wanted wanted, OnMessage onMessage)
    : m_wanted(std::move(wanted)), m_onMessage(std::move(onMessage)) {
  m_body.reserve(kMaxKeptBody);
}

bool IgtlStreamReader::feed(std::span<const unsigned char> bytes) {
  size_t at = 0;
  while (!failed() && at < bytes.size()) {
    if (!m_inBody) {
      const size_t take = std::min(kHeaderSize - m_headerFill, bytes.size() - at);
      std::copy_n(bytes.data() + at, take, m_headerBytes.data() + m_headerFill);
      m_headerFill += take;
      at += take;
      if (m_headerFill < kHeaderSize) break;
      m_headerFill = 0;
      const auto header = decodeHeader(m_headerBytes);
      if (!header) {
        m_error = "not an OpenIGTLink header (a version other than 1 to 3, or a type name that is not ASCII)";
        break;
      }
      m_header = *header;
      m_keeping = m_wanted(m_header);
      if (m_keeping && m_header.bodySize > kMaxKeptBody) {
        m_error = "a " + std::string(m_header.typeName()) + " message of " + std::to_string(m_header.bodySize) +
                  " bytes (at most " + std::to_string(kMaxKeptBody) + " are read)";
        break;
      }
      if (!m_keeping && m_header.bodySize > kMaxSkippedBody) {
        m_error = "a message body of " + std::to_string(m_header.bodySize) + " bytes";
        break;
      }
      m_bodyLeft = m_header.bodySize;
      m_body.clear();
      m_inBody = true;
    }
    const size_t take = static_cast<size_t>(std::min<uint64_t>(m_bodyLeft, bytes.size() - at));
    if (m_keeping) m_body.insert(m_body.end(), bytes.data() + at, bytes.data() + at + take);
    at += take;
    m_bodyLeft -= take;
    if (m_bodyLeft > 0) break;
    m_inBody = false;
    if (!m_keeping) {
      ++m_skipped;
      continue;
    }
    if (crc64(m_body) != m_header.crc) {
      m_error = "a " + std::string(m_header.typeName()) + " message whose CRC does not match its body";
      break;
    }
    const auto content = messageContent(m_header, m_body);
    if (!content) {
      m_error = "a version " + std::to_string(m_header.version) + " message whose extended header does not fit";
      break;
    }
    ++m_kept;
    m_onMessage(m_header, *content);
  }
  return !failed();
}

}  // namespace trephine::openigtlink
