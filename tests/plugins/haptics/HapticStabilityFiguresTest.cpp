// The haptic stability figures of the summary (passivity observer, force steps
// beyond the device's motion, force reversals) on hand-built logs with
// closed-form values.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "framework/logs/HapticFrameLog.h"

namespace trephine {
namespace {

constexpr double kT = 0.001;  // s, frame period of every log here

// A log of n frames at 1 kHz: device position and force on the hand per frame k.
HapticFrameLog makeLog(size_t n, const std::function<Vec3(size_t)>& device, const std::function<Vec3(size_t)>& force) {
  HapticFrameLog log(n);
  for (size_t k = 0; k < n; ++k) {
    HapticFrame f;
    f.t = static_cast<double>(k) * kT;
    f.device = device(k);
    f.force = force(k);
    log.record(f);
  }
  return log;
}

TEST(HapticStabilityFiguresTest, SpringLoadedAndUnloadedOnOnePathReturnsItsEnergyUpToTheHold) {
  // The device presses D = N d into a wall of stiffness k in steps of d per
  // frame and comes back the same way; F = k depth pushes it out. With the
  // force held over each frame, loading stores k d^2 N (N - 1) / 2 and
  // unloading gives back k d^2 N (N + 1) / 2: E ends at -k d^2 N = -k D d, the
  // energy the hold generates (0.2% of the k D^2 / 2 = 1 mJ stored at the bottom).
  constexpr double k = 2.0, d = 0.001;  // N/mm, mm
  constexpr size_t N = 1000;
  const auto depth = [&](size_t i) { return d * static_cast<double>(i <= N ? i : 2 * N - i); };
  const HapticFrameLog log = makeLog(
      2 * N + 1, [&](size_t i) { return Vec3(0, 0, -depth(i)); }, [&](size_t i) { return Vec3(0, 0, k * depth(i)); });
  const HapticStats s = log.stats();
  EXPECT_NEAR(s.energyIn_mJ, -k * d * d * N, 1e-12);
  EXPECT_NEAR(s.minEnergyIn_mJ, -k * d * d * N, 1e-12) << "lowest at the end";
  // The largest fall in 100 ms: the first 100 frames of unloading, k d^2 (100 N - 4950).
  EXPECT_NEAR(s.maxGeneratedPer100ms_mJ, k * d * d * (100.0 * N - 4950.0), 1e-9);
}

TEST(HapticStabilityFiguresTest, TheDevicesDampingPaysForTheHoldExactlyBelowTheSampledDataBound) {
  // The press and release above, counted with a device damping b: each frame's
  // move d dissipates at least b d^2 / T, 2 N frames of it, against the
  // k d^2 N the hold generates: E_b ends at (2 b / T - k) N d^2. Colgate and
  // Schenkelberg's b > k T / 2 is where it turns negative.
  constexpr double b = 0.00645, d = 0.001;  // N*s/mm (HandDevice's grip), mm
  constexpr size_t N = 1000;
  const double bound = 2.0 * b / kT;  // N/mm, 12.9
  const auto depth = [&](size_t i) { return d * static_cast<double>(i <= N ? i : 2 * N - i); };
  for (const double k : {0.99 * bound, 1.01 * bound}) {
    HapticFrameLog log = makeLog(
        2 * N + 1, [&](size_t i) { return Vec3(0, 0, -depth(i)); }, [&](size_t i) { return Vec3(0, 0, k * depth(i)); });
    EXPECT_FALSE(log.stats().hasDeviceDamping) << "no damping handed: no figure";
    log.setDeviceDamping(b);
    const HapticStats s = log.stats();
    ASSERT_TRUE(s.hasDeviceDamping);
    EXPECT_EQ(s.deviceDamping, b);
    EXPECT_NEAR(s.energyIn_mJ, -k * d * d * N, 1e-12) << "the environment alone is not passive";
    EXPECT_NEAR(s.energyInWithDevice_mJ, (bound - k) * N * d * d, 1e-12);
    if (k < bound)
      EXPECT_EQ(s.minEnergyInWithDevice_mJ, 0.0) << k;
    else
      EXPECT_NEAR(s.minEnergyInWithDevice_mJ, (bound - k) * N * d * d, 1e-12) << k << ": lowest at the end";
  }
}

TEST(HapticStabilityFiguresTest, ProxyGeneratedIsWhatTheSpringGainsBeyondTheDevicesMove) {
  // The device still, the spring's anchor lifted by h a frame for M frames
  // from a depth p0: the spring gains k ((p0 + M h)^2 - p0^2) / 2 that no
  // motion of the device explains. Pressed in by the device against an anchor
  // that stays, it gains as much and none of it counts.
  constexpr double k = 8.0, p0 = 0.1, h = 0.002;  // N/mm, mm, mm
  constexpr size_t M = 50;
  const auto frames = [&](bool deviceMoves) {
    HapticFrameLog log(M + 1);
    for (size_t i = 0; i <= M; ++i) {
      const double p = p0 + h * static_cast<double>(i);
      HapticFrame f;
      f.t = static_cast<double>(i) * kT;
      f.device = deviceMoves ? Vec3(0, 0, p0 - p) : Vec3::Zero();
      f.penetration = p;
      f.normal = Vec3(0, 0, 1);
      f.force = k * p * f.normal;
      f.contacts = 1;
      log.record(f);
    }
    log.setRenderingGains(k, 0.0);
    return log.stats();
  };
  const double gained = 0.5 * k * (std::pow(p0 + M * h, 2) - p0 * p0);  // mJ
  EXPECT_NEAR(frames(false).proxyGenerated_mJ, gained, 1e-12);
  EXPECT_NEAR(frames(true).proxyGenerated_mJ, 0.0, 1e-12);
}

TEST(HapticStabilityFiguresTest, OneSidedDamperDissipatesItsIntegral) {
  // Down at v for 0.5 s against F = b v (a damper that acts only pressing in),
  // back up at v freely: E = b v^2 * 0.5 s, and never below 0.
  constexpr double b = 0.002, v = 10.0;  // N*s/mm, mm/s
  constexpr size_t half = 500;
  const HapticFrameLog log = makeLog(
      2 * half + 1, [&](size_t i) { return Vec3(0, 0, -v * kT * static_cast<double>(i <= half ? i : 2 * half - i)); },
      [&](size_t i) { return i < half ? Vec3(0, 0, b * v) : Vec3::Zero(); });
  const HapticStats s = log.stats();
  EXPECT_NEAR(s.energyIn_mJ, b * v * v * 0.5, 1e-12);
  EXPECT_EQ(s.minEnergyIn_mJ, 0.0);
  EXPECT_EQ(s.maxGeneratedPer100ms_mJ, 0.0);
}

TEST(HapticStabilityFiguresTest, ForcePushingAlongTheMotionGeneratesEnergy) {
  // F = +c v pushes the hand the way it moves (a negative damper): E = -c v^2 t.
  constexpr double c = 0.003, v = 20.0;  // N*s/mm, mm/s
  constexpr size_t n = 1001;             // 1 s
  const HapticFrameLog log = makeLog(
      n, [&](size_t i) { return Vec3(v * kT * static_cast<double>(i), 0, 0); },
      [&](size_t) { return Vec3(c * v, 0, 0); });
  const HapticStats s = log.stats();
  EXPECT_NEAR(s.energyIn_mJ, -c * v * v * 1.0, 1e-12);
  EXPECT_NEAR(s.minEnergyIn_mJ, -c * v * v * 1.0, 1e-12);
  EXPECT_NEAR(s.maxGeneratedPer100ms_mJ, c * v * v * 0.1, 1e-12);
}

TEST(HapticStabilityFiguresTest, DelayedSpringGeneratesWhatItsLagPredicts) {
  // x = A sin(w t), F = -k x delayed by m frames: a spring lagging by tau acts
  // on a cycle like a negative damping and generates pi k A^2 sin(w tau) per
  // cycle; the hold adds half a frame to the delay (tau = (m + 1/2) T).
  constexpr double A = 1.0, k = 1.0, f = 2.0;  // mm, N/mm, Hz
  constexpr int m = 10;
  constexpr size_t cycles = 5, n = static_cast<size_t>(cycles / f / kT) + 1;
  const double w = 2.0 * std::numbers::pi * f;
  const auto x = [&](double t) { return A * std::sin(w * t); };
  const HapticFrameLog log = makeLog(
      n, [&](size_t i) { return Vec3(x(static_cast<double>(i) * kT), 0, 0); },
      [&](size_t i) { return Vec3(-k * x((static_cast<double>(i) - m) * kT), 0, 0); });
  const HapticStats s = log.stats();
  const double perCycle = std::numbers::pi * k * A * A * std::sin(w * (m + 0.5) * kT);  // mJ
  EXPECT_NEAR(s.energyIn_mJ, -perCycle * cycles, 0.01 * perCycle * cycles);
  EXPECT_LT(s.minEnergyIn_mJ, -0.9 * perCycle * cycles);
  EXPECT_GT(s.maxGeneratedPer100ms_mJ, 0.0);
}

TEST(HapticStabilityFiguresTest, UnexplainedStepsAreWhatTheGainsDoNotAccountFor) {
  // A spring-damper along z on a smooth press explains every step of its force.
  constexpr double k = 2.0, b = 0.002;  // N/mm, N*s/mm
  constexpr size_t n = 1000;
  const auto z = [&](size_t i) { return -0.5 * (1.0 - std::cos(std::numbers::pi * static_cast<double>(i) / n)); };
  const auto velocity = [&](size_t i) { return i == 0 ? 0.0 : (z(i) - z(i - 1)) / kT; };
  const auto spring = [&](size_t i) { return Vec3(0, 0, -k * z(i) - b * velocity(i)); };
  HapticFrameLog smooth = makeLog(
      n, [&](size_t i) { return Vec3(0, 0, z(i)); }, spring);
  EXPECT_FALSE(smooth.stats().hasUnexplainedSteps) << "no gains handed: no figure";
  smooth.setRenderingGains(k, b);
  HapticStats s = smooth.stats();
  EXPECT_TRUE(s.hasUnexplainedSteps);
  EXPECT_LT(s.unexplainedStepMax, 1e-12);

  // The same press with a 1 N jump at frame 600 that no motion explains.
  HapticFrameLog jump = makeLog(
      n, [&](size_t i) { return Vec3(0, 0, z(i)); },
      [&](size_t i) { return Vec3(spring(i) + Vec3(0, 0, i >= 600 ? 1.0 : 0.0)); });
  jump.setRenderingGains(k, b);
  s = jump.stats();
  // 1 N less what the damping's share of that frame's step hides (b |dv| ~ 3e-6 N).
  EXPECT_NEAR(s.unexplainedStepMax, 1.0, 1e-4);
  EXPECT_LT(s.unexplainedStepP99, 1e-12) << "one frame in a thousand";
  EXPECT_GT(s.forceStepMax, 1.0) << "the raw step also has the motion's share";
}

TEST(HapticStabilityFiguresTest, ReversalsCountForcesThatTurnBackAboveHalfANewton) {
  // +-1 N alternating over 10 frames: 9 reversals; +-0.3 N: none (noise around zero).
  const auto alternating = [](double magnitude) {
    return [magnitude](size_t i) { return Vec3(0, 0, i % 2 ? -magnitude : magnitude); };
  };
  const auto still = [](size_t) { return Vec3::Zero(); };
  EXPECT_EQ(makeLog(10, still, alternating(1.0)).stats().forceReversals, 9u);
  EXPECT_EQ(makeLog(10, still, alternating(0.3)).stats().forceReversals, 0u);
}

}  // namespace
}  // namespace trephine
