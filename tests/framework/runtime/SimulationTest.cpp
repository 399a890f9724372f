// End-to-end behaviour of a run: determinism, replay, device rejection,
// outputs, interrupts, and that only what the scene names runs.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <thread>
#include <sstream>

#include "framework/devices/DeviceStream.h"
#include "framework/runtime/RunOutputs.h"
#include "framework/runtime/Simulation.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

using test::loadScene;
using test::messages;

// The plane-touch example with the device part replaceable.
std::string planeScene(const std::string& device, const std::string& extra = "") {
  return R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <AnalyticPlane name="plane"/>
  )" + device +
         R"(
  <SphereTool name="burr" radius="2.5" device="@device"/>
  <SpringForce name="force" tool="@burr" target="@plane" stiffness="2" rate="1000"/>
  )" + extra +
         R"(
</Node>)";
}

const std::string kScripted =
    R"(<ScriptedDevice name="device" path="random-walk" target="@plane" tipOffset="2.5" depth="1" walkDuration="0.5" rate="1000"/>)";

std::string traceOf(const Simulation& simulation) {
  std::ostringstream out;
  writeTraceCsv(simulation, out);
  return out.str();
}

std::unique_ptr<Simulation> mustLoad(const std::string& xml, const SimulationOptions& options = {}) {
  Diagnostics d;
  auto simulation = loadScene(xml, d, options);
  EXPECT_TRUE(simulation) << messages(d);
  return simulation;
}

TEST(SimulationTest, SameSceneSeedAndInputGiveByteIdenticalTraces) {
  SimulationOptions options;
  options.seed = 7;
  auto first = mustLoad(planeScene(kScripted), options);
  auto second = mustLoad(planeScene(kScripted), options);
  ASSERT_TRUE(first && second);
  first->run();
  second->run();
  const std::string trace = traceOf(*first);
  EXPECT_GT(first->hapticLog().stats().contactFrames, 100u) << "the walk touches the plane";
  EXPECT_EQ(trace, traceOf(*second));

  options.seed = 8;
  auto other = mustLoad(planeScene(kScripted), options);
  other->run();
  EXPECT_NE(trace, traceOf(*other)) << "the seed changes the random walk";
}

TEST(SimulationTest, ARecordedRunReplayedThroughReplayDeviceGivesTheSameTrace) {
  test::TempDir dir;
  auto recorded = mustLoad(planeScene(kScripted));
  ASSERT_TRUE(recorded);
  recorded->run();
  recorded->writeOutputs(dir.path());
  const auto stream = dir / "device.device.csv";
  ASSERT_TRUE(std::filesystem::exists(stream));

  auto replayed =
      mustLoad(planeScene(R"(<ReplayDevice name="device" file=")" + stream.string() + R"(" rate="1000"/>)"));
  ASSERT_TRUE(replayed);
  EXPECT_DOUBLE_EQ(replayed->plan().duration, recorded->plan().duration) << "replay lasts as long as the recording";
  replayed->run();
  EXPECT_EQ(traceOf(*replayed), traceOf(*recorded));
}

TEST(SimulationTest, NaNDeviceSamplesAreRejectedCountedAndThePoseHeld) {
  auto simulation = mustLoad(planeScene(
      R"(<ScriptedDevice name="device" target="@plane" tipOffset="2.5" nanTimes="0.6 0.9 0.9005" rate="1000"/>)"));
  ASSERT_TRUE(simulation);
  simulation->run();
  const HapticStats stats = simulation->hapticLog().stats();
  EXPECT_EQ(stats.nanFrames, 0u) << "a rejected sample never reaches the trace";
  EXPECT_EQ(test::componentCounterAt(*simulation, "device", "rejected_non_finite"), 3.0);
  EXPECT_EQ(test::componentCounterAt(*simulation, "device", "rejected_jump"), 0.0);
  // Two streaks (0.6 s; 0.9 and 0.901 s): one event when each starts and one when it ends.
  ASSERT_EQ(simulation->events().size(), 4u);
  EXPECT_STREQ(simulation->events()[0].kind, "device_rejected");
  EXPECT_STREQ(simulation->events()[1].kind, "device_recovered");
  EXPECT_DOUBLE_EQ(simulation->events()[2].t, 0.9);
  // The frame at 0.6 s shows the pose of 0.599 s.
  const HapticFrameLog& log = simulation->hapticLog();
  EXPECT_EQ(log[600].device, log[599].device);
  EXPECT_EQ(log[600].force, log[599].force) << "force is held with the pose";
}

TEST(SimulationTest, ACounterTheComponentDoesNotReportFailsTheTest) {
  // The tests read counters through these helpers, so a renamed or dropped
  // counter fails them instead of skipping their check.
  auto simulation = mustLoad(planeScene(kScripted));
  ASSERT_TRUE(simulation);
  double value = 0;
  EXPECT_NONFATAL_FAILURE(value = test::componentCounterAt(*simulation, "device", "no_such_counter"),
                          "reports no counter no_such_counter");
  EXPECT_TRUE(std::isnan(value)) << "so that no comparison passes on it";
  EXPECT_NONFATAL_FAILURE(test::componentCounter(*simulation, "NoSuchType", "rejected_jump"), "no NoSuchType");
  EXPECT_NONFATAL_FAILURE(test::componentCounterAt(*simulation, "nowhere", "rejected_jump"), "no component nowhere");
  EXPECT_EQ(test::componentCounterAt(*simulation, "device", "rejected_jump"), 0.0) << "and a reported one is read";
}

TEST(SimulationTest, OnlyTheRatesInTheSceneGetGroups) {
  auto withoutRecorder = mustLoad(planeScene(kScripted));
  ASSERT_TRUE(withoutRecorder);
  ASSERT_EQ(withoutRecorder->scheduler().groups().size(), 1u) << "no recorder, no recorder group or thread";
  EXPECT_EQ(withoutRecorder->scheduler().groups()[0].rateHz, 1000.0);

  auto withRecorder = mustLoad(planeScene(kScripted, R"(<Recorder source="@force" rate="60"/>)"));
  ASSERT_TRUE(withRecorder);
  EXPECT_EQ(withRecorder->scheduler().groups().size(), 2u);
}

TEST(SimulationTest, RecorderSamplesThePublishedValuesAtItsOwnRate) {
  test::TempDir dir;
  SimulationOptions options;
  options.duration = 1.0;
  auto simulation = mustLoad(planeScene(kScripted, R"(<Recorder name="rec" source="@force" rate="60"/>)"), options);
  ASSERT_TRUE(simulation);
  simulation->run();
  simulation->writeOutputs(dir.path());
  const std::string csv = test::readFile(dir / "recording.rec.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 61) << "header plus 60 rows in one second";
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "t,source_t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,force_x,force_y,force_z,penetration");
}

TEST(SimulationTest, OutputsFollowTheRunContract) {
  test::TempDir dir;
  SimulationOptions options;
  options.duration = 0.25;
  auto simulation = mustLoad(planeScene(kScripted), options);
  ASSERT_TRUE(simulation);
  simulation->run();
  const auto written = simulation->writeOutputs(dir.path());
  EXPECT_EQ(written, (std::vector<std::string>{"trace.csv", "timings.csv", "summary.json", "device.device.csv"}));
  const std::string trace = test::readFile(dir / "trace.csv");
  EXPECT_EQ(trace.substr(0, trace.find('\n')), kTraceHeader);
  EXPECT_EQ(std::count(trace.begin(), trace.end(), '\n'), 251);
  const std::string timings = test::readFile(dir / "timings.csv");
  EXPECT_EQ(std::count(timings.begin(), timings.end(), '\n'), 1 + 2 * 250) << "one row per call of device and force";
  const std::string summary = test::readFile(dir / "summary.json");
  for (const char* key :
       {"\"scene\"", "\"seed\"", "\"mode\": \"virtual\"", "\"sim_time_s\": 0.25", "\"wall_time_s\"", "\"components\"",
        "\"/device\"", "\"groups\"", "\"1000\"", "\"haptics\"", "\"frames\": 250", "\"force_step_N\"",
        "\"proxy_inside_frames\"", "\"drilling\"", "\"voxels_removed\"", "\"events\"", "\"complete\": true"})
    EXPECT_NE(summary.find(key), std::string::npos) << key << " missing from summary.json";
}

TEST(SimulationTest, AnInterruptedRunStillWritesWhatItMeasured) {
  test::TempDir dir;
  auto simulation = mustLoad(planeScene(kScripted));
  ASSERT_TRUE(simulation);
  std::atomic<bool> stop{true};
  simulation->run(stop);
  simulation->markInterrupted("interrupted by SIGINT");
  simulation->writeOutputs(dir.path());
  const std::string summary = test::readFile(dir / "summary.json");
  EXPECT_NE(summary.find("\"complete\": false"), std::string::npos);
  EXPECT_NE(summary.find("\"reason\": \"interrupted by SIGINT\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "trace.csv"));
}

TEST(SimulationTest, OnlyOneComponentMayWriteTheHapticTrace) {
  Diagnostics d;
  auto simulation = loadScene(planeScene(kScripted, R"(<SpringForce name="second" tool="@burr" target="@plane"/>)"), d);
  EXPECT_FALSE(simulation);
  EXPECT_NE(messages(d).find("only one component per scene writes the haptic trace; /force already does"),
            std::string::npos)
      << messages(d);
}

TEST(SimulationTest, InitErrorsPointAtTheComponent) {
  Diagnostics d;
  auto simulation = loadScene(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <AnalyticPlane name="plane" normal="0 0 0"/>
</Node>)",
                              d);
  EXPECT_FALSE(simulation);
  EXPECT_NE(messages(d).find("inline.xml:3:39: error: invalid normal of AnalyticPlane 'plane': the normal must not be zero"), std::string::npos)
      << messages(d);
}

}  // namespace
}  // namespace trephine

namespace trephine {
namespace {

TEST(SimulationRulesTest, LinksBetweenTickingComponentsOfDifferentRatesAreRefused) {
  Diagnostics d;
  EXPECT_FALSE(
      test::loadScene(planeScene(R"(<ScriptedDevice name="device" target="@plane" tipOffset="2.5" rate="500"/>)"), d));
  // The force (1000 Hz) reads the device (500 Hz) through the passive tool.
  EXPECT_NE(messages(d).find("inline.xml:7:35: error: SpringForce 'force' (1000 Hz) reads ScriptedDevice '/device' "
                             "(500 Hz) through its links"),
            std::string::npos)
      << messages(d);
}

TEST(SimulationRulesTest, WithinAGroupLinkTargetsTickFirstWhateverTheDocumentOrder) {
  auto simulation = mustLoad(R"(<Node name="root">
  <RequiredPlugin name="analytic"/>
  <RequiredPlugin name="haptics"/>
  <SpringForce name="force" tool="@burr" target="@plane" rate="1000"/>
  <SphereTool name="burr" radius="2.5" device="@device"/>
  <ScriptedDevice name="device" path="waypoints" waypoints="0 1 2 3  1 1 2 3" rate="1000"/>
  <AnalyticPlane name="plane"/>
</Node>)");
  ASSERT_TRUE(simulation);
  simulation->run();
  EXPECT_EQ(simulation->hapticLog()[0].device, Vec3(1, 2, 3)) << "the force saw this frame's device pose";
}

TEST(SimulationRulesTest, OutputFileNamesAreCheckedWhenTheSceneLoads) {
  // Not at the end of a run, when the measurements would be lost.
  const std::pair<const char*, const char*> cases[] = {
      {"../escaped.csv", "cannot write '../escaped.csv': it is not a plain file name"},
      {"summary.json", "cannot write 'summary.json': it is one of the run's own files"},
      {"device.device.csv", "cannot write 'device.device.csv': /device writes it"},
  };
  for (const auto& [name, message] : cases) {
    Diagnostics d;
    EXPECT_FALSE(loadScene(planeScene(kScripted, std::string(R"(<Recorder source="@force" file=")") + name + "\"/>"), d))
        << name;
    EXPECT_NE(messages(d).find(std::string("inline.xml:8:35: error: Recorder 'Recorder' ") + message), std::string::npos)
        << messages(d);
  }
}

TEST(SimulationRulesTest, TooLongARunIsAnErrorNamingWhoAskedForIt) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(
      planeScene(
          R"(<ScriptedDevice name="device" path="random-walk" target="@plane" walkDuration="1e9" rate="1000"/>)"),
      d));
  EXPECT_NE(messages(d).find("ScriptedDevice 'device': asks for a run of"), std::string::npos) << messages(d);
}

TEST(SimulationRulesTest, AnApproachFromInsideTheTargetIsRefused) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(planeScene(R"(<ScriptedDevice name="device" target="@plane" direction="0 0 1"/>)"), d));
  EXPECT_NE(messages(d).find("misses /plane"), std::string::npos) << messages(d);
}

TEST(SimulationRulesTest, ALoopingReplayKeepsTimeMovingAndIsNotAJump) {
  test::TempDir dir;
  const auto file =
      dir.write("stroke.csv",
                "t,x,y,z,qw,qx,qy,qz,buttons\n0,0,0,10,1,0,0,0,0\n0.05,40,0,10,1,0,0,0,0\n0.099,80,0,10,1,0,0,0,0\n");
  SimulationOptions options;
  options.duration = 0.35;
  auto simulation = mustLoad(
      planeScene(R"(<ReplayDevice name="device" loop="true" maxSpeed="1000000" file=")" + file.string() + "\"/>"),
      options);
  ASSERT_TRUE(simulation);
  simulation->run();
  EXPECT_EQ(test::componentCounterAt(*simulation, "device", "rejected_jump"), 0.0) << "starting over is intended";
  simulation->writeOutputs(dir / "run");
  const auto recorded = readDeviceStream(dir / "run/device.device.csv");
  EXPECT_TRUE(recorded.error.empty()) << recorded.error << ": the recording of a looping replay replays";
  EXPECT_EQ(recorded.samples.size(), 350u);
}

}  // namespace
}  // namespace trephine

namespace trephine {
namespace {

// In real time each rate group of 500 Hz or more is a thread that polls the
// clock: one more of them than cores is warned of at load.
TEST(SimulationRulesTest, MorePollingRealTimeGroupsThanCoresIsWarnedOf) {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const auto scene = [](unsigned groups) {
    std::string xml = "<Node name=\"root\">\n  <RequiredPlugin name=\"haptics\"/>\n";
    for (unsigned g = 0; g < groups; ++g)
      xml += "  <ScriptedDevice name=\"d" + std::to_string(g) + "\" rate=\"1000\" group=\"g" + std::to_string(g) +
             "\"/>\n";
    return xml + "</Node>";
  };
  SimulationOptions options;
  options.realtime = true;
  for (const unsigned groups : {cores, cores + 1}) {
    Diagnostics d;
    ASSERT_TRUE(test::loadScene(scene(groups), d, options)) << test::messages(d);
    const bool warned = test::messages(d).find("rate groups of 500 Hz or more") != std::string::npos;
    EXPECT_EQ(warned, groups > cores) << groups << " groups on " << cores << " cores: " << test::messages(d);
  }
  Diagnostics virtualTime;
  ASSERT_TRUE(test::loadScene(scene(cores + 1), virtualTime)) << "one thread in virtual time: nothing to warn of";
  EXPECT_TRUE(virtualTime.all().empty()) << test::messages(virtualTime);
}

}  // namespace
}  // namespace trephine
