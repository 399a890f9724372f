#include "plugins/voxel_skull/io/HeaderText.h"

#include <charconv>
#include <cstdio>
#include <limits>

#include "framework/core/Strings.h"

namespace trephine::voxel {

HeaderLine headerLineAt(std::string_view text, size_t start) {
  HeaderLine line;
  if (start >= text.size()) {
    line.next = text.size();
    return line;
  }
  const size_t newline = text.find('\n', start);
  const size_t end = newline == std::string_view::npos ? text.size() : newline;
  line.text = text.substr(start, end - start);
  if (!line.text.empty() && line.text.back() == '\r') line.text.remove_suffix(1);
  line.terminated = newline != std::string_view::npos;
  line.next = line.terminated ? newline + 1 : text.size();
  return line;
}

namespace {
char lowerAscii(char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; }
}  // namespace

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (lowerAscii(a[i]) != lowerAscii(b[i])) return false;
  return true;
}

std::string toLower(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = lowerAscii(c);
  return lower;
}

std::optional<int64_t> parseInteger(std::string_view word) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  int64_t value = 0;
  const auto result = std::from_chars(word.data(), word.data() + word.size(), value);
  if (word.empty() || result.ec != std::errc() || result.ptr != word.data() + word.size()) return std::nullopt;
  return value;
}

std::optional<double> parseReal(std::string_view word) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  double value = 0;
  const auto result = std::from_chars(word.data(), word.data() + word.size(), value);
  if (word.empty() || result.ec != std::errc() || result.ptr != word.data() + word.size()) return std::nullopt;
  return value;
}

std::optional<std::vector<double>> parseReals(std::string_view text, size_t count) {
  const std::vector<std::string_view> words = splitWhitespace(text);
  if (words.size() != count) return std::nullopt;
  std::vector<double> values;
  for (std::string_view word : words) {
    const std::optional<double> value = parseReal(word);
    if (!value) return std::nullopt;
    values.push_back(*value);
  }
  return values;
}

std::optional<std::vector<int64_t>> parseIntegers(std::string_view text, size_t count) {
  const std::vector<std::string_view> words = splitWhitespace(text);
  if (words.size() != count) return std::nullopt;
  std::vector<int64_t> values;
  for (std::string_view word : words) {
    const std::optional<int64_t> value = parseInteger(word);
    if (!value) return std::nullopt;
    values.push_back(*value);
  }
  return values;
}

bool isPlainFileName(std::string_view name) {
  for (char c : name)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return false;
  return !name.empty();
}

std::string quoteForMessage(std::string_view text) {
  constexpr size_t kMaxShown = 80;
  std::string out = "'";
  for (size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f && c != '\\') {
      out += static_cast<char>(c);
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", c);
      out += escaped;
    }
  }
  if (text.size() > kMaxShown) out += "...";
  return out + "'";
}

}  // namespace trephine::voxel
