#pragma once
// Reading the text of a mesh file token by token or line by line while
// counting lines, so that every error can say where it is
// ("cube.ele:12: ..."). The text stays in memory; tokens are views into it.
// Numbers are parsed strictly: the whole token must be the number.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "framework/formats/encoding/TextTokens.h"

namespace trephine::formats {

class TextCursor {
 public:
  // `comment`: a character that starts a comment running to the end of the
  // line ('#' in TetGen and Medit files), or '\0' for none.
  TextCursor(std::string_view text, const std::filesystem::path& file, char comment = '\0');

  const std::filesystem::path& file() const { return m_file; }
  // Line of the last token or line handed out (1-based).
  size_t line() const { return m_tokenLine; }
  size_t bytesLeft() const { return m_text.size() - m_pos; }
  // True when only blank space and comments remain.
  bool atEnd();

  // The next whitespace-separated token on any line; empty at the end of the text.
  std::string_view next();
  // The next token without consuming it.
  std::string_view peek();
  // The tokens of the next line that has any (blank and comment lines are
  // skipped); false at the end of the text.
  bool nextLine(std::vector<std::string_view>& tokens);
  // The rest of the current line, untouched, and moves to the next line.
  std::string_view restOfLine();
  // The next `count` raw bytes (binary data after a header line); the caller
  // checked bytesLeft().
  std::string_view take(size_t count);

  // The next token as a whole number; fails naming `what` when the text ends
  // (truncated) or the token is not one.
  int64_t nextInteger(const std::string& what);

  // `token` as coordinate `axis` (0, 1, 2: x, y, z; mm) of `owner` ("node
  // 7"); fails when it is not a finite number.
  double coordinate(std::string_view token, int axis, const std::string& owner) const;

  // Throws TetMeshReadError naming the file and line().
  [[noreturn]] void fail(const std::string& problem) const;
  // Refuses a count read from the file before anything is reserved for it:
  // negative, above `maxCount`, or more records than the remaining bytes can
  // hold at `minBytesEach` bytes per record.
  void checkCount(int64_t count, int64_t maxCount, uint64_t minBytesEach, const std::string& what) const;

 private:
  void skipBlank();

  std::string_view m_text;
  std::filesystem::path m_file;
  char m_comment;
  size_t m_pos = 0;
  size_t m_line = 1;       // line at m_pos
  size_t m_tokenLine = 1;  // line of the last token handed out
};

}  // namespace trephine::formats
