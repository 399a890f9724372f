#pragma once
// Reading back the arrays the project's VTK XML writers append (raw, zlib
// blocks, UInt64 headers), by hand: the tests' own decoder, independent of
// the writer's code.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "framework/formats/encoding/Inflate.h"

namespace trephine::test {

// The values of the appended array at `offset` (raw, zlib blocks, UInt64 header).
template <class T>
inline std::vector<T> appendedArray(const std::string& file, uint64_t offset) {
  const size_t start = file.find("<AppendedData encoding=\"raw\">\n_");
  EXPECT_NE(start, std::string::npos);
  const uint8_t* data = reinterpret_cast<const uint8_t*>(file.data()) + start + 31 + offset;
  auto header = [&](size_t i) {
    uint64_t v;
    std::memcpy(&v, data + 8 * i, 8);
    return v;
  };
  const uint64_t blocks = header(0), blockBytes = header(1), last = header(2);
  std::vector<uint8_t> bytes(blocks ? (blocks - 1) * blockBytes + last : 0);
  const uint8_t* block = data + 8 * (3 + blocks);
  for (uint64_t b = 0; b < blocks; ++b) {
    const uint64_t size = header(3 + b);
    const std::span<uint8_t> out(bytes.data() + b * blockBytes, b + 1 == blocks ? last : blockBytes);
    EXPECT_FALSE(formats::inflateExactly({block, size}, out)) << "block " << b;
    block += size;
  }
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

// The offset of the appended DataArray named `name` (the first one).
inline uint64_t appendedOffset(const std::string& file, const std::string& name) {
  const size_t at = file.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return UINT64_MAX;
  const size_t offset = file.find("offset=\"", at);
  return std::stoull(file.substr(offset + 8));
}

}  // namespace trephine::test
