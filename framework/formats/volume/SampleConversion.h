#pragma once
// Turning the stored samples of a file into the int16 codes of a
// DensityVolume, in two passes over the file's own typed buffer (first the
// range, then the codes) so no double copy of the volume is ever made.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>

#include "framework/data/DensityVolume.h"
#include "framework/formats/encoding/NumberType.h"

namespace trephine::formats {

struct SampleLayout {
  NumberType type = NumberType::kInt16;
  bool bigEndian = false;  // byte order of multi-byte samples in the buffer
};

// density = slope * sample + intercept (NIfTI scl_slope / scl_inter; identity elsewhere).
struct SampleScaling {
  double slope = 1;
  double intercept = 0;
  bool isIdentity() const { return slope == 1 && intercept == 0; }
};

struct SampleRange {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();
  bool allIntegers = true;
  std::optional<size_t> firstNonFinite;  // index in the buffer of the first NaN or infinite density
};

// Pass one: the density range and whether every density is an integer. Stops
// at the first NaN or infinite density.
SampleRange scanSamples(std::span<const uint8_t> bytes, SampleLayout layout, SampleScaling scaling);

// Where the stored samples go: stored sample (i, j, k) (i fastest, `dims`)
// lands at index base + i step[0] + j step[1] + k step[2] of the codes (steps
// may be negative: flipped axes; any order: permuted axes).
struct SamplePlacement {
  std::array<int64_t, 3> dims{0, 0, 0};
  std::array<int64_t, 3> step{1, 0, 0};
  int64_t base = 0;
};

// Pass two: encodes every density with `encoding` (rounded, clamped to the code range).
void encodeSamples(std::span<const uint8_t> bytes, SampleLayout layout, SampleScaling scaling,
                   const DensityEncoding& encoding, const SamplePlacement& placement, std::span<VoxelCode> codes);

}  // namespace trephine::formats
