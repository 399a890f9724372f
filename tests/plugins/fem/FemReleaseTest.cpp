// After the FEM diverges (and is reset to rest), the haptic side lets go: the
// proxy is released to the device with a haptic_released event, the force it
// rendered fades to zero along ForceFeedback's releaseRamp (not a step), and
// no force ever pulls the hand towards a place the tool is not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "tests/plugins/fem/FemFailureScenes.h"
#include "tests/plugins/fem/FemScenes.h"
#include "tests/support/TestSupport.h"

namespace trephine::fem {
namespace {

constexpr double kRamp = 0.02;  // s, releaseRamp: 20 frames at 1 kHz

std::unique_ptr<Simulation> runPress(const test::TempDir& dir, const Vec3* stray = nullptr) {
  const auto mesh = scenes::writeCube(dir / "cube.mesh", stray);
  return scenes::runFor(scenes::cubePressScene(mesh, R"(releaseRamp=")" + std::to_string(kRamp) + R"(")"), 2.0,
                        dir / "out");
}

std::vector<double> eventTimes(const Simulation& simulation, const char* kind) {
  std::vector<double> times;
  const EventLog& events = simulation.events();
  for (size_t i = 0; i < events.size(); ++i)
    if (std::strcmp(events[i].kind, kind) == 0) times.push_back(events[i].t);
  return times;
}

TEST(FemReleaseTest, EachDivergenceReleasesTheProxyWithAnEventAndTheForceFadesAlongTheRamp) {
  test::TempDir dir;
  auto simulation = runPress(dir);
  ASSERT_TRUE(simulation);
  const std::vector<double> diverged = eventTimes(*simulation, "fem_diverged");
  const std::vector<double> released = eventTimes(*simulation, "haptic_released");
  ASSERT_GT(diverged.size(), 0u) << "the press makes the FEM diverge";
  ASSERT_GT(released.size(), 0u);
  // Each release follows a divergence within a few frames (the rest shape
  // reaches the haptic frame through the channel).
  for (double t : released) {
    bool follows = false;
    for (double d : diverged) follows = follows || (t >= d && t - d <= 0.005);
    EXPECT_TRUE(follows) << "release at " << t << " s";
  }
  const HapticFrameLog& log = simulation->hapticLog();
  const size_t rampFrames = size_t(std::lround(kRamp * 1000));
  size_t ramps = 0;
  for (double t : released) {
    size_t i = 0;
    while (i < log.size() && log[i].t < t - 1e-9) ++i;
    if (i == 0 || i + rampFrames >= log.size()) continue;
    const Vec3 before = log[i - 1].force;
    if (before.norm() < 0.05) continue;  // nothing to fade
    // A release within a ramp of the one before continues or restarts that
    // fade: the first of a series is checked.
    bool fresh = true;
    for (double earlier : released) fresh = fresh && !(earlier < t - 1e-9 && earlier > t - kRamp - 1e-9);
    if (!fresh) continue;
    ++ramps;
    // Linear to zero over rampFrames: frame k after the release renders
    // (1 - (k + 1) / rampFrames) of the force before it, in its direction
    // (until another release, which fades from where this one got).
    size_t next = i + rampFrames;
    for (double later : released)
      if (later > t + 1e-9)
        for (size_t j = i + 1; j < next; ++j)
          if (log[j].t >= later - 1e-9) next = j;
    for (size_t k = 0; i + k < next; ++k) {
      const Vec3 expected = (1.0 - double(k + 1) / double(rampFrames)) * before;
      ASSERT_LT((log[i + k].force - expected).norm(), 1e-12) << "t = " << log[i + k].t;
    }
  }
  EXPECT_GT(ramps, 0u) << "a release while a force was rendered";
  EXPECT_EQ(test::componentCounter(*simulation, "GodObjectProxy", "releases"), double(released.size()));
  // A release while the proxy is still let go continues the fade under way.
  EXPECT_GE(test::componentCounter(*simulation, "ForceFeedback", "release_ramps"), double(ramps));
  EXPECT_LE(test::componentCounter(*simulation, "ForceFeedback", "release_ramps"), double(released.size()));
}

TEST(FemReleaseTest, TheForceNeverPullsTheHandIntoTheBrainAndTheProxyStaysAboveIt) {
  // The probe presses from above: a force with a downward part pulls the hand
  // towards the brain, where the tool is not. The mesh carries a stray node
  // far away, as an exported file may.
  test::TempDir dir;
  const Vec3 stray(1000, 1000, 1000);
  auto simulation = runPress(dir, &stray);
  ASSERT_TRUE(simulation);
  const HapticFrameLog& log = simulation->hapticLog();
  const std::vector<double> released = eventTimes(*simulation, "haptic_released");
  // A force with a downward part is allowed only around a release: in the
  // few frames before it, while the diverging shape pushes the proxy aside
  // (a tenth of a millimetre down, hundredths of a newton, which rounding in
  // other builds may or may not give), and along the fade of that force.
  // Before the release was made, the hand was pulled at up to 3.3 N for as
  // long as it stayed (1,429 frames here).
  size_t pulling = 0, unexplained = 0;
  double mostDown = 0;  // N
  double proxyLowest = INFINITY;
  for (size_t i = 0; i < log.size(); ++i) {
    proxyLowest = std::min(proxyLowest, log[i].proxy.z());
    if (!(log[i].force.z() < -1e-6)) continue;
    ++pulling;
    mostDown = std::min(mostDown, log[i].force.z());
    bool nearRelease = false;
    for (double r : released) nearRelease = nearRelease || (log[i].t >= r - 0.005 && log[i].t <= r + kRamp + 1e-9);
    if (!nearRelease) ++unexplained;
  }
  EXPECT_EQ(unexplained, 0u) << pulling << " frames pull the hand down";
  EXPECT_GT(mostDown, -0.1) << "N";
  // The device goes down to 5 mm below the top (z = 10) plus the probe's radius.
  EXPECT_GT(proxyLowest, 10.0 - 5.0);
}

}  // namespace
}  // namespace trephine::fem
