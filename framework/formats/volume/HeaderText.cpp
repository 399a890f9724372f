#include "framework/formats/volume/HeaderText.h"

#include <charconv>
#include <cstdio>
#include <limits>

#include "framework/core/Strings.h"

namespace trephine::formats {

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

}  // namespace trephine::formats
