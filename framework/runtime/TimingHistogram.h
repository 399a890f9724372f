#pragma once
// Fixed-size log-linear histogram of durations in nanoseconds: 64 buckets per
// power of two (relative error under 1.6%), exact count, sum and max.
// Recording is a few integer operations with no allocation, so the scheduler
// can time every call of a 1 kHz loop.
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

namespace trephine {

struct TimingSummary {
  uint64_t count = 0;
  double p50 = 0, p90 = 0, p99 = 0, max = 0, mean = 0;  // µs
};

class TimingHistogram {
 public:
  void record(uint64_t nanoseconds) {
    ++m_buckets[bucketOf(nanoseconds)];
    ++m_count;
    m_sum += nanoseconds;
    if (nanoseconds > m_max) m_max = nanoseconds;
  }

  uint64_t count() const { return m_count; }
  uint64_t maxNs() const { return m_max; }
  // The value (ns) at quantile q in [0, 1]: the upper edge of the bucket
  // holding that rank, capped by the exact maximum.
  double quantileNs(double q) const;
  TimingSummary summary() const;
  void merge(const TimingHistogram& other);

 private:
  static constexpr int kSubBits = 6;  // 64 sub-buckets per octave
  static constexpr uint64_t kSub = uint64_t{1} << kSubBits;
  static constexpr int kOctaves = 64 - kSubBits;
  static constexpr size_t kBuckets = (kOctaves + 1) * kSub;

  static size_t bucketOf(uint64_t v) {
    if (v < kSub) return static_cast<size_t>(v);      // exact below 64 ns
    const int octave = std::bit_width(v) - kSubBits;  // >= 1
    return static_cast<size_t>(octave) * kSub + static_cast<size_t>((v >> (octave - 1)) - kSub);
  }
  static uint64_t upperEdgeOf(size_t bucket);

  std::array<uint32_t, kBuckets> m_buckets{};
  uint64_t m_count = 0;
  uint64_t m_sum = 0;
  uint64_t m_max = 0;
};

}  // namespace trephine
