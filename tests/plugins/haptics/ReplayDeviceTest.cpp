// ReplayDevice: exact samples at recorded times, interpolation between them, clear errors.
#include <gtest/gtest.h>

#include "framework/core/Strings.h"
#include "framework/devices/HapticDevice.h"
#include "tests/support/TestSupport.h"

namespace trephine {
namespace {

std::string replayScene(const std::string& file, const std::string& extra = "") {
  return R"(<Node name="root">
  <RequiredPlugin name="haptics"/>
  <ReplayDevice name="device" file=")" +
         file + "\" " + extra + R"(/>
</Node>)";
}

TEST(ReplayDeviceTest, InterpolatesBetweenSamplesRecordedAtALowerRate) {
  test::TempDir dir;
  const auto file = dir.write("slow.csv", "t,x,y,z,qw,qx,qy,qz,buttons\n0,0,0,0,1,0,0,0,0\n0.01,10,0,0,1,0,0,0,1\n");
  Diagnostics d;
  SimulationOptions options;
  options.duration = 0.02;
  auto simulation = test::loadScene(replayScene(file.string()), d, options);
  ASSERT_TRUE(simulation) << test::messages(d);
  auto* device = dynamic_cast<HapticDevice*>(simulation->scene().findComponent("device"));
  ASSERT_NE(device, nullptr);
  // Step through the run by hand: 4 ms in, the device is 40% of the way.
  TickContext context{0.004, 0.001, 4, nullptr};
  device->tick(context);
  EXPECT_NEAR(device->state().pose.position.x(), 4.0, 1e-12);
  context.t = 0.015;
  device->tick(context);
  EXPECT_DOUBLE_EQ(device->state().pose.position.x(), 10.0) << "holds the last sample after the end";
  EXPECT_EQ(device->state().buttons, 1u);
}

TEST(ReplayDeviceTest, AMalformedStreamIsAnErrorAtTheFileField) {
  test::TempDir dir;
  const auto file = dir.write("bad.csv", "t,x,y,z,qw,qx,qy,qz,buttons\n0,0,0,0,1,0,0,0,0\n0.001,1,2\n");
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(replayScene(file.string()), d));
  EXPECT_NE(test::messages(d).find("inline.xml:3:37: error: invalid file of ReplayDevice 'device': " + file.string() +
                                   ":3: expected 9 columns (t,x,y,z,qw,qx,qy,qz,buttons), got 3"),
            std::string::npos)
      << test::messages(d);
}

// Times that cannot be seconds from the run's start would replay as no motion
// or crushed into a frame: each is an error that says what t must be.
TEST(ReplayDeviceTest, TimesInOtherUnitsOrClocksAreErrors) {
  test::TempDir dir;
  const std::string header = "t,x,y,z,qw,qx,qy,qz,buttons\n";
  struct Case {
    const char* name;
    std::string rows;
    const char* expected;
  };
  std::string nanoseconds;  // 1 kHz samples written in seconds divided by 1e6 again
  for (int k = 0; k < 2000; ++k) nanoseconds += formatDouble(k * 1e-9) + "," + std::to_string(k) + ",0,0,1,0,0,0,0\n";
  const Case cases[] = {
      {"negative.csv", "-3,0,0,0,1,0,0,0,0\n-2,1,0,0,1,0,0,0,0\n", "every sample is before the run starts at t = 0"},
      {"epoch.csv", "1764300000,0,0,0,1,0,0,0,0\n1764300000.001,1,0,0,1,0,0,0,0\n",
       "the first sample is at 1764300000 s, after the longest run (3600 s)"},
      {"crushed.csv", nanoseconds, "2000 samples over 2e-06 s are 1e-09 s apart, a hundredth of the device's period "
                                   "(0.001 s) or less"},
  };
  for (const Case& c : cases) {
    const auto file = dir.write(c.name, header + c.rows);
    Diagnostics d;
    EXPECT_FALSE(test::loadScene(replayScene(file.string()), d)) << c.name;
    const std::string text = test::messages(d);
    EXPECT_NE(text.find("inline.xml:3:37: error: invalid file of ReplayDevice 'device': " + file.string() + ": "),
              std::string::npos)
        << text;
    EXPECT_NE(text.find(c.expected), std::string::npos) << text;
    EXPECT_NE(text.find("the column t is in seconds from the start of the run"), std::string::npos) << text;
  }
  // A recording at 10 kHz replayed at 1 kHz is fine: a tenth of the period.
  std::string fast;
  for (int k = 0; k < 100; ++k) fast += formatDouble(k * 1e-4) + ",0,0,0,1,0,0,0,0\n";
  Diagnostics d;
  EXPECT_TRUE(test::loadScene(replayScene(dir.write("fast.csv", header + fast).string()), d)) << test::messages(d);
}

TEST(ReplayDeviceTest, AByteOrderMarkBeforeTheHeaderIsSkipped) {
  test::TempDir dir;
  const auto file = dir.write("bom.csv", "\xEF\xBB\xBFt,x,y,z,qw,qx,qy,qz,buttons\n0,0,0,0,1,0,0,0,0\n");
  Diagnostics d;
  EXPECT_TRUE(test::loadScene(replayScene(file.string()), d)) << test::messages(d);
}

TEST(ReplayDeviceTest, AMissingFileIsReportedWhereItIsNamed) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(replayScene("nowhere.csv"), d));
  EXPECT_NE(test::messages(d).find("inline.xml:3:37: error: invalid file of ReplayDevice 'device': file not found"),
            std::string::npos)
      << test::messages(d);
}

}  // namespace
}  // namespace trephine
