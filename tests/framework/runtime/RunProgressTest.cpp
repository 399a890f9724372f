// A long run's progress: the line's figures, and the reports a run in real
// time gives while it goes on (read from another thread: run under TSan).
#include <gtest/gtest.h>

#include <sstream>

#include "framework/runtime/RunProgress.h"
#include "framework/runtime/Simulation.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

TEST(RunProgressTest, TheLineSaysTheSimulatedTimeTheWallTimeAndWhatIsLeftAtThePaceSoFar) {
  EXPECT_EQ(RunProgress::describe(4, 18, 2), "progress  4.0 s of 18 s simulated, 2.0 s wall, about 7.0 s left");
  EXPECT_EQ(RunProgress::describe(90, 120, 300), "progress  90 s of 120 s simulated, 300 s wall, about 100 s left");
  // Nothing simulated yet: no estimate; done: nothing left to say.
  EXPECT_EQ(RunProgress::describe(0, 18, 3), "progress  0.0 s of 18 s simulated, 3.0 s wall");
  EXPECT_EQ(RunProgress::describe(18, 18, 9), "progress  18 s of 18 s simulated, 9.0 s wall");
}

TEST(RunProgressTest, ARunInRealTimeIsReportedWhileItGoesOnWithTheSimulatedTimeGrowing) {
  const std::string scene = test::readFile(test::sourceDir() / "scenes/examples/plane_touch.xml");
  Diagnostics diagnostics;
  SimulationOptions options;
  options.realtime = true;
  options.duration = 1.2;
  auto simulation = test::loadScene(scene, diagnostics, options);
  ASSERT_TRUE(simulation) << test::messages(diagnostics);
  std::ostringstream out;
  {
    RunProgress progress(simulation->scheduler(), 1.2, out, 0.2, false);
    simulation->run();
  }
  std::vector<double> simulated;
  std::istringstream lines(out.str());
  for (std::string line; std::getline(lines, line);) {
    ASSERT_TRUE(line.starts_with("progress  ")) << line;
    simulated.push_back(std::stod(line.substr(10)));
  }
  // About one report per 0.2 s of a 1.2 s run (the machine may be slow to wake).
  ASSERT_GE(simulated.size(), 3u) << out.str();
  EXPECT_LE(simulated.size(), 7u) << out.str();
  for (size_t i = 1; i < simulated.size(); ++i) EXPECT_GE(simulated[i], simulated[i - 1]) << out.str();
  EXPECT_GT(simulated.back(), 0.4) << out.str();
  EXPECT_LE(simulated.back(), 1.2) << out.str();
}

TEST(RunProgressTest, ARunShorterThanTheIntervalSaysNothing) {
  auto simulation = test::runScene(test::readFile(test::sourceDir() / "scenes/examples/plane_touch.xml"));
  ASSERT_TRUE(simulation);
  std::ostringstream out;
  { RunProgress progress(simulation->scheduler(), 2.3, out, 60, true); }
  EXPECT_EQ(out.str(), "");
}

}  // namespace
}  // namespace trephine
