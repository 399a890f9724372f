#include "framework/formats/mesh/TextCursor.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "framework/formats/mesh/TetMeshReader.h"

namespace trephine::formats {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

}  // namespace

TextCursor::TextCursor(std::string_view text, const std::filesystem::path& file, char comment)
    : m_text(text), m_file(file), m_comment(comment) {}

void TextCursor::skipBlank() {
  while (m_pos < m_text.size()) {
    const char c = m_text[m_pos];
    if (c == '\n') {
      ++m_line;
      ++m_pos;
    } else if (isBlank(c)) {
      ++m_pos;
    } else if (c == m_comment && c != '\0') {
      while (m_pos < m_text.size() && m_text[m_pos] != '\n') ++m_pos;
    } else {
      return;
    }
  }
}

bool TextCursor::atEnd() {
  skipBlank();
  return m_pos == m_text.size();
}

std::string_view TextCursor::next() {
  skipBlank();
  m_tokenLine = m_line;
  const size_t start = m_pos;
  while (m_pos < m_text.size()) {
    const char c = m_text[m_pos];
    if (c == '\n' || isBlank(c) || (c == m_comment && c != '\0')) break;
    ++m_pos;
  }
  return m_text.substr(start, m_pos - start);
}

std::string_view TextCursor::peek() {
  const size_t pos = m_pos;
  const size_t line = m_line;
  const size_t tokenLine = m_tokenLine;
  const std::string_view token = next();
  m_pos = pos;
  m_line = line;
  m_tokenLine = tokenLine;
  return token;
}

bool TextCursor::nextLine(std::vector<std::string_view>& tokens) {
  tokens.clear();
  while (m_pos < m_text.size()) {
    m_tokenLine = m_line;
    bool inComment = false;
    size_t start = std::string_view::npos;
    while (m_pos < m_text.size() && m_text[m_pos] != '\n') {
      const char c = m_text[m_pos];
      if (!inComment && (isBlank(c) || (c == m_comment && c != '\0'))) {
        if (start != std::string_view::npos) tokens.push_back(m_text.substr(start, m_pos - start));
        start = std::string_view::npos;
        inComment = c == m_comment && c != '\0';
      } else if (!inComment && start == std::string_view::npos) {
        start = m_pos;
      }
      ++m_pos;
    }
    if (start != std::string_view::npos) tokens.push_back(m_text.substr(start, m_pos - start));
    if (m_pos < m_text.size()) {
      ++m_pos;  // the '\n'
      ++m_line;
    }
    if (!tokens.empty()) return true;
  }
  return false;
}

std::string_view TextCursor::restOfLine() {
  m_tokenLine = m_line;
  const size_t start = m_pos;
  while (m_pos < m_text.size() && m_text[m_pos] != '\n') ++m_pos;
  const std::string_view rest = m_text.substr(start, m_pos - start);
  if (m_pos < m_text.size()) {
    ++m_pos;
    ++m_line;
  }
  return rest;
}

std::string_view TextCursor::take(size_t count) {
  if (count > bytesLeft()) fail("internal error: read past the end of the data");
  const std::string_view bytes = m_text.substr(m_pos, count);
  m_pos += count;
  // Newline bytes inside binary data still count, as an editor would show the lines after it.
  for (const char c : bytes) m_line += c == '\n' ? 1 : 0;
  return bytes;
}

void TextCursor::fail(const std::string& problem) const { throw TetMeshReadError(m_file, m_tokenLine, problem); }

int64_t TextCursor::nextInteger(const std::string& what) {
  const std::string_view token = next();
  if (token.empty()) fail("the file ends where " + what + " should be (truncated)");
  const std::optional<int64_t> value = parseInteger(token);
  if (!value) fail(what + " is " + quoteForMessage(token) + ", expected a whole number");
  return *value;
}

double TextCursor::coordinate(std::string_view token, int axis, const std::string& owner) const {
  const std::optional<double> value = parseReal(token);
  const char name = "xyz"[axis];
  if (!value) fail(owner + ": " + name + " coordinate " + quoteForMessage(token) + " is not a number");
  if (!std::isfinite(*value))
    fail(owner + " has a non-finite " + name + " coordinate " + quoteForMessage(token) +
         " (expected a finite number of mm)");
  return *value;
}

void TextCursor::checkCount(int64_t count, int64_t maxCount, uint64_t minBytesEach, const std::string& what) const {
  if (count < 0) fail("the number of " + what + " is " + std::to_string(count) + ", expected 0 or more");
  if (count > maxCount)
    fail("the file declares " + std::to_string(count) + " " + what + ", more than the " + std::to_string(maxCount) +
         " supported");
  if (uint64_t(count) * minBytesEach > bytesLeft() + 1)
    fail("the file declares " + std::to_string(count) + " " + what + " but only " + std::to_string(bytesLeft()) +
         " bytes follow (truncated file or corrupt count)");
}

}  // namespace trephine::formats
