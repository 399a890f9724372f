// ReplayDevice: exact samples at recorded times, interpolation between them, clear errors.
#include <gtest/gtest.h>

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

TEST(ReplayDeviceTest, AMissingFileIsReportedWhereItIsNamed) {
  Diagnostics d;
  EXPECT_FALSE(test::loadScene(replayScene("nowhere.csv"), d));
  EXPECT_NE(test::messages(d).find("inline.xml:3:37: error: invalid file of ReplayDevice 'device': file not found"),
            std::string::npos)
      << test::messages(d);
}

}  // namespace
}  // namespace trephine
