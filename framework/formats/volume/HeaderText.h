#pragma once
// Parsing the text headers of MetaImage and NRRD files: lines, words and
// numbers, strictly (a whole word must be the number) so that a corrupt
// header is reported instead of being half-read.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "framework/formats/encoding/TextTokens.h"

namespace trephine::formats {

// One header line without its line ending, and where the next line starts (byte offset).
struct HeaderLine {
  std::string_view text;
  size_t next = 0;
  bool terminated = false;  // ended by '\n' (false: the text ran out first)
};
// The line starting at byte `start` of `text` ("\n" or "\r\n" endings).
HeaderLine headerLineAt(std::string_view text, size_t start);

// Exactly `count` whitespace-separated numbers, or nothing.
std::optional<std::vector<double>> parseReals(std::string_view text, size_t count);
std::optional<std::vector<int64_t>> parseIntegers(std::string_view text, size_t count);

// True when `name` has no control characters (NUL, newline, ...): usable as a data file name.
bool isPlainFileName(std::string_view name);


// The bytes as text, for header parsing.
inline std::string_view asText(std::span<const uint8_t> bytes) {
  return std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

}  // namespace trephine::formats
