#include "framework/core/Strings.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numeric>

namespace trephine {

size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  std::iota(row.begin(), row.end(), size_t{0});
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      const bool same =
          std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::optional<std::string> closestMatch(std::string_view word, const std::vector<std::string>& candidates) {
  const size_t limit = std::max<size_t>(2, word.size() / 3);
  std::optional<std::string> best;
  size_t bestDistance = limit + 1;
  for (const std::string& candidate : candidates) {
    const size_t d = editDistance(word, candidate);
    // Never a change of every letter: "x" is no typo of "a", nor "ab" of "xy".
    if (d < bestDistance && d < word.size()) {
      bestDistance = d;
      best = candidate;
    }
  }
  return best;
}

std::string didYouMean(std::string_view word, const std::vector<std::string>& candidates) {
  if (auto match = closestMatch(word, candidates)) return ", did you mean '" + *match + "'?";
  return "";
}

std::string_view trim(std::string_view s) {
  const auto isSpace = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> splitWhitespace(std::string_view s) {
  std::vector<std::string_view> parts;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    const size_t start = i;
    while (i < s.size() && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i > start) parts.push_back(s.substr(start, i - start));
  }
  return parts;
}

std::string formatDouble(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string visiblyQuoted(std::string_view text) {
  // UTF-8 sequences of characters that show as nothing or as a plain space.
  static constexpr struct {
    std::string_view bytes;
    const char* name;
  } kInvisible[] = {
      {"\xEF\xBB\xBF", "\\u{FEFF}"}, {"\xE2\x80\x8B", "\\u{200B}"}, {"\xE2\x80\x8C", "\\u{200C}"},
      {"\xE2\x80\x8D", "\\u{200D}"}, {"\xE2\x81\xA0", "\\u{2060}"}, {"\xC2\xA0", "\\u{00A0}"},
      {"\xE2\x80\xAF", "\\u{202F}"},
  };
  std::string out = "'";
  for (size_t i = 0; i < text.size();) {
    bool named = false;
    for (const auto& invisible : kInvisible) {
      if (text.substr(i).starts_with(invisible.bytes)) {
        out += invisible.name;
        i += invisible.bytes.size();
        named = true;
        break;
      }
    }
    if (named) continue;
    const unsigned char c = static_cast<unsigned char>(text[i++]);
    if (c < 0x20 || c == 0x7F) {
      static constexpr char kHex[] = "0123456789ABCDEF";
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
    } else {
      out += char(c);
    }
  }
  return out + "'";
}

}  // namespace trephine
