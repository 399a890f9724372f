// Runs that go wrong still end cleanly and say what happened.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <thread>

#include "tests/plugins/TestPluginFixture.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using RunFailureTest = TestPluginFixture;

// Runs `scene` for 1 s with the test plugins, expects the run-time failure
// exit code and an incomplete run, and returns its summary.json.
std::string runToFailure(const std::filesystem::path& scene, const std::filesystem::path& out) {
  std::string printed;
  EXPECT_EQ(test::runProgram({"run", scene.string(), "--duration", "1", "--out", out.string()}, &printed,
                             "TREPHINE_PLUGIN_PATH=" TREPHINE_TEST_PLUGIN_DIR),
            3)
      << printed;
  const std::string summary = test::readFile(out / "summary.json");
  EXPECT_NE(summary.find("\"complete\": false"), std::string::npos) << summary;
  return summary;
}

TEST_F(RunFailureTest, AThrowingTickEndsTheRunNamingTheComponentAndKeepsWhatWasMeasured) {
  test::TempDir dir;
  const auto scene = dir.write("throws.xml", R"(<Node name="root">
  <RequiredPlugin name="test_faults"/>
  <Node name="bad"><ThrowingComponent name="thrower" failAt="0.25"/></Node>
</Node>
)");
  const std::string summary = runToFailure(scene, dir / "out");
  EXPECT_NE(summary.find("\"reason\": \"run-time error: /bad/thrower: deliberate failure\""), std::string::npos)
      << summary;
  EXPECT_NE(summary.find("\"calls\": 250"), std::string::npos) << "the 250 calls before the failure were timed";
  EXPECT_NE(summary.find("\"t\": 0.25,\n      \"kind\": \"tick_failed\",\n      \"component\": \"/bad/thrower\""),
            std::string::npos)
      << "the failure is an event too";
}

// A collision back-end that throws inside a query (as a third-party library
// might): the target catches it at its boundary, the run ends incomplete
// naming the target and the back-end, and every output is written.
TEST_F(RunFailureTest, ABackEndThatThrowsEndsTheRunNamingTheTargetWithEveryOutputWritten) {
  struct Target {
    std::string plugin, element, path;
  };
  const Target targets[] = {
      {"voxel_skull", R"(<VoxelSkull name="target" file="phantom:halfspace?voxel=1&amp;size=20" isovalue="500")",
       "/patient/target"},
      {"tetra_brain", R"(<TetraBrain name="target" file="phantom:cube?cells=4")", "/patient/target"}};
  for (const Target& target : targets) {
    SCOPED_TRACE(target.plugin);
    test::TempDir dir;
    const auto scene = dir.write("throws.xml", R"(<Node name="root">
  <RequiredPlugin name=")" + target.plugin + R"("/>
  <RequiredPlugin name="haptics"/>
  <RequiredPlugin name="test_faults"/>
  <Node name="patient">
    )" + target.element + R"( backend="throwing"/>
  </Node>
  <ScriptedDevice name="device" target="@/patient/target" path="approach-press-slide" direction="0 0 -1"
                  depth="1" slideDistance="5" tipOffset="2.5" record="false"/>
  <PointshellTool name="burr" radius="2.5" device="@device"/>
  <GodObjectProxy name="proxy" tool="@burr" target="@/patient/target"/>
  <ForceFeedback name="force" proxy="@proxy" stiffness="2" maxForce="3.3"/>
</Node>
)");
    const std::string summary = runToFailure(scene, dir / "out");
    EXPECT_NE(
        summary.find("collision back-end \\\"throwing\\\" of " + target.path + " failed: deliberate back-end failure"),
        std::string::npos)
        << summary;
    // The frames before the failure are in the trace: the header and one row per frame.
    const std::string trace = test::readFile(dir / "out/trace.csv");
    EXPECT_GE(std::count(trace.begin(), trace.end(), '\n'), 100) << trace.substr(0, 300);
    EXPECT_TRUE(std::filesystem::exists(dir / "out/timings.csv"));
  }
}

TEST_F(RunFailureTest, VirtualTimeCountsStepsLongerThanTheirPeriodAsDeadlineMisses) {
  Diagnostics d;
  SimulationOptions options;
  options.duration = 0.02;
  auto simulation = test::loadScene(R"(<Node name="root">
  <RequiredPlugin name="test_faults"/>
  <SlowComponent name="slow" busy="0.0015" rate="1000"/>
</Node>)",
                                    d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  simulation->run();
  EXPECT_EQ(simulation->scheduler().groups()[0].deadlineMisses, 20u) << "every 1.5 ms step misses its 1 ms period";
}

TEST_F(RunFailureTest, CtrlCStopsARealTimeRunAndItsOutputsAreWritten) {
  test::TempDir dir;
  const std::string command = "TREPHINE_PLUGIN_PATH=" TREPHINE_TEST_PLUGIN_DIR " '" + test::programPath().string() +
                              "' run '" + (test::sourceDir() / "scenes/examples/plane_touch.xml").string() +
                              "' --realtime --duration 30 --out '" + (dir / "out").string() +
                              "' > /dev/null 2>&1 & echo $! > '" + (dir / "pid").string() + "'; wait $!";
  std::thread run([&] { EXPECT_EQ(std::system(command.c_str()) >> 8, 3) << "interrupted runs exit with 3"; });
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  const int pid = std::atoi(test::readFile(dir / "pid").c_str());
  ASSERT_GT(pid, 0);
  kill(pid, SIGINT);
  run.join();
  const std::string summary = test::readFile(dir / "out/summary.json");
  EXPECT_NE(summary.find("\"complete\": false"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"reason\": \"interrupted by SIGINT\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"calls_per_s\""), std::string::npos) << "real-time figures are reported";
  const std::string trace = test::readFile(dir / "out/trace.csv");
  EXPECT_GT(std::count(trace.begin(), trace.end(), '\n'), 100) << "frames measured before the stop are kept";
}

}  // namespace
}  // namespace trephine
