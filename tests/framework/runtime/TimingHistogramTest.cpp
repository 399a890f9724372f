#include <gtest/gtest.h>

#include "framework/runtime/TimingHistogram.h"

namespace trephine {
namespace {

TEST(TimingHistogramTest, QuantilesAreWithinTheBucketResolution) {
  TimingHistogram h;
  for (uint64_t ns = 1; ns <= 100000; ++ns) h.record(ns);  // uniform 1 ns .. 100 µs
  const TimingSummary s = h.summary();
  EXPECT_EQ(s.count, 100000u);
  // 64 sub-buckets per octave: relative error below 1/64.
  EXPECT_NEAR(s.p50, 50.0, 50.0 / 64);
  EXPECT_NEAR(s.p90, 90.0, 90.0 / 64);
  EXPECT_NEAR(s.p99, 99.0, 99.0 / 64);
  EXPECT_DOUBLE_EQ(s.max, 100.0);
  EXPECT_NEAR(s.mean, 50.0005, 1e-9);
}

TEST(TimingHistogramTest, SmallValuesAreExactAndHugeValuesDoNotOverflow) {
  TimingHistogram h;
  h.record(0);
  h.record(63);
  h.record(~uint64_t{0} >> 1);
  EXPECT_EQ(h.quantileNs(0.34), 63.0);
  EXPECT_EQ(h.count(), 3u);
  EXPECT_EQ(h.maxNs(), ~uint64_t{0} >> 1);
}

TEST(TimingHistogramTest, EmptyHistogramReportsZeros) {
  const TimingSummary s = TimingHistogram().summary();
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.p99, 0.0);
  EXPECT_EQ(s.max, 0.0);
}

}  // namespace
}  // namespace trephine
