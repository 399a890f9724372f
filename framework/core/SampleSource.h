#pragma once
// A component that publishes a row of named figures each tick on its
// "samples" channel, for a Recorder in another rate group to pick up.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "framework/core/Component.h"

namespace trephine {

inline constexpr size_t kMaxSampleValues = 32;

struct Sample {
  double t = 0;  // s, time of the tick that produced it
  std::array<double, kMaxSampleValues> values{};
};

inline constexpr const char* kSampleChannel = "samples";

// An interface, implemented by components next to Component. The component
// publishes `Sample`s on the channel named kSampleChannel in its init().
class SampleSource {
 public:
  static constexpr std::string_view kTypeName = "SampleSource";
  virtual ~SampleSource() = default;
  // Names (with units) of the values, at most kMaxSampleValues.
  virtual std::vector<std::string> sampleColumns() const = 0;
};

}  // namespace trephine
