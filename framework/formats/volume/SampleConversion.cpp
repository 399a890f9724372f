#include "framework/formats/volume/SampleConversion.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace trephine::formats {

namespace {

template <typename T>
using BitsOf = std::conditional_t<
    sizeof(T) == 1, uint8_t,
    std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;

template <typename Bits>
Bits byteSwapped(Bits bits) {
  if constexpr (sizeof(Bits) == 2) return __builtin_bswap16(bits);
  if constexpr (sizeof(Bits) == 4) return __builtin_bswap32(bits);
  if constexpr (sizeof(Bits) == 8) return __builtin_bswap64(bits);
  return bits;
}

// The sample at `p` (unaligned), byte-swapped when the file's order is not the machine's.
template <typename T>
T loadSample(const uint8_t* p, bool swap) {
  BitsOf<T> bits;
  std::memcpy(&bits, p, sizeof bits);
  if (swap) bits = byteSwapped(bits);
  return std::bit_cast<T>(bits);
}

bool needsSwap(SampleLayout layout) { return layout.bigEndian != (std::endian::native == std::endian::big); }

template <typename T>
SampleRange scanTyped(std::span<const uint8_t> bytes, bool swap, SampleScaling scaling) {
  SampleRange range;
  const size_t count = bytes.size() / sizeof(T);
  const uint8_t* p = bytes.data();
  constexpr bool kInteger = std::is_integral_v<T>;
  if (kInteger && scaling.isIdentity()) {
    // Integers of at most 32 bits: always finite and integral.
    T lo = std::numeric_limits<T>::max(), hi = std::numeric_limits<T>::lowest();
    for (size_t n = 0; n < count; ++n, p += sizeof(T)) {
      const T v = loadSample<T>(p, swap);
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (count > 0) {
      range.min = double(lo);
      range.max = double(hi);
    }
    return range;
  }
  for (size_t n = 0; n < count; ++n, p += sizeof(T)) {
    const double v = scaling.slope * double(loadSample<T>(p, swap)) + scaling.intercept;
    if (!std::isfinite(v)) {
      range.firstNonFinite = n;
      return range;
    }
    range.min = std::min(range.min, v);
    range.max = std::max(range.max, v);
    if (range.allIntegers && v != std::floor(v)) range.allIntegers = false;
  }
  return range;
}

template <typename T>
void encodeTyped(std::span<const uint8_t> bytes, bool swap, SampleScaling scaling, const DensityEncoding& encoding,
                 const SamplePlacement& placement, std::span<VoxelCode> codes) {
  constexpr double kCodeMin = std::numeric_limits<VoxelCode>::min();
  constexpr double kCodeMax = std::numeric_limits<VoxelCode>::max();
  // code = (density - offset) / scale. Not folded into one multiply-add: with
  // a tiny scale, slope / scale can overflow and inf * 0 is NaN. Unfolded,
  // each density is finite and inside the range pass one found, so
  // |density - offset| is at most about half the range and the code at most
  // about 32768 (the scale is a normal double, its reciprocal finite).
  const double perCode = 1.0 / encoding.scale;
  const auto [ni, nj, nk] = placement.dims;
  const auto [si, sj, sk] = placement.step;
  const uint8_t* p = bytes.data();
  VoxelCode* out = codes.data();
  for (int64_t k = 0; k < nk; ++k) {
    for (int64_t j = 0; j < nj; ++j) {
      int64_t target = placement.base + j * sj + k * sk;
      for (int64_t i = 0; i < ni; ++i, p += sizeof(T), target += si) {
        const double density = scaling.slope * double(loadSample<T>(p, swap)) + scaling.intercept;
        const double code = std::round((density - encoding.offset) * perCode);
        out[target] = static_cast<VoxelCode>(std::clamp(code, kCodeMin, kCodeMax));
      }
    }
  }
}

template <template <typename> class Action>
auto dispatch(NumberType type, auto&&... arguments) {
  switch (type) {
    case NumberType::kInt8:
      return Action<int8_t>::run(arguments...);
    case NumberType::kUInt8:
      return Action<uint8_t>::run(arguments...);
    case NumberType::kInt16:
      return Action<int16_t>::run(arguments...);
    case NumberType::kUInt16:
      return Action<uint16_t>::run(arguments...);
    case NumberType::kInt32:
      return Action<int32_t>::run(arguments...);
    case NumberType::kUInt32:
      return Action<uint32_t>::run(arguments...);
    case NumberType::kInt64:
      return Action<int64_t>::run(arguments...);
    case NumberType::kUInt64:
      return Action<uint64_t>::run(arguments...);
    case NumberType::kFloat32:
      return Action<float>::run(arguments...);
    case NumberType::kFloat64:
      return Action<double>::run(arguments...);
  }
  return Action<uint8_t>::run(arguments...);
}

template <typename T>
struct Scan {
  static SampleRange run(std::span<const uint8_t> bytes, bool swap, SampleScaling scaling) {
    return scanTyped<T>(bytes, swap, scaling);
  }
};

template <typename T>
struct Encode {
  static void run(std::span<const uint8_t> bytes, bool swap, SampleScaling scaling, const DensityEncoding& encoding,
                  const SamplePlacement& placement, std::span<VoxelCode> codes) {
    encodeTyped<T>(bytes, swap, scaling, encoding, placement, codes);
  }
};

}  // namespace

SampleRange scanSamples(std::span<const uint8_t> bytes, SampleLayout layout, SampleScaling scaling) {
  return dispatch<Scan>(layout.type, bytes, needsSwap(layout), scaling);
}

void encodeSamples(std::span<const uint8_t> bytes, SampleLayout layout, SampleScaling scaling,
                   const DensityEncoding& encoding, const SamplePlacement& placement, std::span<VoxelCode> codes) {
  dispatch<Encode>(layout.type, bytes, needsSwap(layout), scaling, encoding, placement, codes);
}

}  // namespace trephine::formats
