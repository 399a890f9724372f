#include "framework/formats/encoding/Base64.h"

#include <array>
#include <cstdint>

namespace trephine::formats {

namespace {

constexpr int8_t kNotBase64 = -1;
constexpr int8_t kSpace = -2;
constexpr int8_t kPad = -3;

constexpr std::array<int8_t, 256> makeTable() {
  std::array<int8_t, 256> table{};
  for (auto& entry : table) entry = kNotBase64;
  constexpr std::string_view kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  for (size_t i = 0; i < kAlphabet.size(); ++i) table[uint8_t(kAlphabet[i])] = int8_t(i);
  for (const char c : {' ', '\t', '\n', '\r', '\v', '\f'}) table[uint8_t(c)] = kSpace;
  table[uint8_t('=')] = kPad;
  return table;
}

constexpr std::array<int8_t, 256> kTable = makeTable();

}  // namespace

bool decodeBase64(std::string_view text, std::string& out, size_t& badOffset) {
  out.clear();
  out.reserve(text.size() / 4 * 3 + 3);
  uint32_t bits = 0;
  int held = 0;  // characters of the current group of four
  // Flushes a group of 2 to 4 characters (12, 18 or 24 bits -> 1, 2 or 3 bytes).
  const auto flush = [&] {
    const uint32_t group = bits << (6 * (4 - held));
    out.push_back(char((group >> 16) & 0xff));
    if (held >= 3) out.push_back(char((group >> 8) & 0xff));
    if (held == 4) out.push_back(char(group & 0xff));
    bits = 0;
    held = 0;
  };
  for (size_t i = 0; i < text.size(); ++i) {
    const int8_t value = kTable[uint8_t(text[i])];
    if (value == kSpace) continue;
    if (value == kPad) {
      // Padding ends a group of 2 or 3 characters; the next stream may follow.
      if (held == 1) {
        badOffset = i;
        return false;
      }
      if (held > 1) flush();
      continue;
    }
    if (value == kNotBase64) {
      badOffset = i;
      return false;
    }
    bits = (bits << 6) | uint32_t(value);
    if (++held == 4) flush();
  }
  if (held == 1) {
    badOffset = text.size();
    return false;
  }
  if (held > 1) flush();
  return true;
}

std::string encodeBase64(std::string_view bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (const size_t rest = bytes.size() - i; rest > 0) {
    const uint32_t v = (uint8_t(bytes[i]) << 16) | (rest == 2 ? uint8_t(bytes[i + 1]) << 8 : 0);
    out += kAlphabet[v >> 18];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace trephine::formats
