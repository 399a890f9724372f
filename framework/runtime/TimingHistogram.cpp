#include "framework/runtime/TimingHistogram.h"

#include <algorithm>
#include <cmath>

namespace trephine {

uint64_t TimingHistogram::upperEdgeOf(size_t bucket) {
  if (bucket < kSub) return bucket;
  const size_t octave = bucket / kSub;
  const uint64_t sub = bucket % kSub;
  // Values in this bucket are [ (kSub + sub) << (octave - 1), (kSub + sub + 1) << (octave - 1) ).
  return ((kSub + sub + 1) << (octave - 1)) - 1;
}

double TimingHistogram::quantileNs(double q) const {
  if (m_count == 0) return 0;
  const uint64_t rank = std::max<uint64_t>(1, static_cast<uint64_t>(std::ceil(q * static_cast<double>(m_count))));
  uint64_t seen = 0;
  for (size_t b = 0; b < kBuckets; ++b) {
    seen += m_buckets[b];
    if (seen >= rank) return static_cast<double>(std::min(upperEdgeOf(b), m_max));
  }
  return static_cast<double>(m_max);
}

TimingSummary TimingHistogram::summary() const {
  TimingSummary s;
  s.count = m_count;
  if (m_count == 0) return s;
  s.p50 = quantileNs(0.50) / 1e3;
  s.p90 = quantileNs(0.90) / 1e3;
  s.p99 = quantileNs(0.99) / 1e3;
  s.max = static_cast<double>(m_max) / 1e3;
  s.mean = static_cast<double>(m_sum) / static_cast<double>(m_count) / 1e3;
  return s;
}

void TimingHistogram::merge(const TimingHistogram& other) {
  for (size_t b = 0; b < kBuckets; ++b) m_buckets[b] += other.m_buckets[b];
  m_count += other.m_count;
  m_sum += other.m_sum;
  m_max = std::max(m_max, other.m_max);
}

}  // namespace trephine
