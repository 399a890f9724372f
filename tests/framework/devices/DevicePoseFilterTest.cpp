#include <gtest/gtest.h>

#include <limits>

#include "framework/devices/DevicePoseFilter.h"
#include "framework/devices/DeviceStream.h"

namespace trephine {
namespace {

constexpr double kPeriod = 0.001;   // s
constexpr double kMaxSpeed = 1000;  // mm/s: at most 1 mm per frame

DeviceSample at(double t, Vec3 p) { return DeviceSample{t, p, Quat::Identity(), 0}; }

TEST(DevicePoseFilterTest, RejectsNaNAndInfinity) {
  DevicePoseFilter filter;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(filter.check(at(0, Vec3(nan, 0, 0)), kMaxSpeed, kPeriod), SampleVerdict::NonFinite);
  EXPECT_EQ(filter.check(at(0, Vec3(0, std::numeric_limits<double>::infinity(), 0)), kMaxSpeed, kPeriod),
            SampleVerdict::NonFinite);
  DeviceSample badRotation = at(0, Vec3::Zero());
  badRotation.orientation = Quat(0, 0, 0, 0);
  EXPECT_EQ(filter.check(badRotation, kMaxSpeed, kPeriod), SampleVerdict::NonFinite);
}

TEST(DevicePoseFilterTest, RejectsJumpsFasterThanTheHandCanMove) {
  DevicePoseFilter filter;
  filter.accept(at(0, Vec3::Zero()));
  EXPECT_EQ(filter.check(at(0.001, Vec3(0.9, 0, 0)), kMaxSpeed, kPeriod), SampleVerdict::Accepted);
  EXPECT_EQ(filter.check(at(0.001, Vec3(1.1, 0, 0)), kMaxSpeed, kPeriod), SampleVerdict::Jump);
  // After three rejected frames the hand may have moved three frames' worth.
  EXPECT_EQ(filter.check(at(0.003, Vec3(2.9, 0, 0)), kMaxSpeed, kPeriod), SampleVerdict::Accepted);
}

TEST(DeviceStreamTest, ReadsWhatItWritesIncludingNonFiniteSamples) {
  std::vector<DeviceSample> samples = {at(0, Vec3(1, 2, 3)), at(0.001, Vec3(0.1, 0.2, 0.30000000000000004))};
  samples.push_back(at(0.002, Vec3(std::numeric_limits<double>::quiet_NaN(), 0, 0)));
  samples[1].buttons = 3;
  std::stringstream stream;
  writeDeviceStream(stream, samples, samples.size());
  const auto read = parseDeviceStream(stream, "memory.csv");
  ASSERT_TRUE(read.error.empty()) << read.error;
  ASSERT_EQ(read.samples.size(), 3u);
  EXPECT_EQ(read.samples[1].position, samples[1].position) << "numbers round-trip exactly";
  EXPECT_EQ(read.samples[1].buttons, 3u);
  EXPECT_TRUE(std::isnan(read.samples[2].position.x()));
}

TEST(DeviceStreamTest, ReportsTheLineAndColumnOfBadInput) {
  std::stringstream wrongHeader("t,x,y\n0,1,2\n");
  EXPECT_EQ(parseDeviceStream(wrongHeader, "a.csv").error,
            "a.csv:1: expected the header t,x,y,z,qw,qx,qy,qz,buttons, got 't,x,y'");
  std::stringstream badNumber("t,x,y,z,qw,qx,qy,qz,buttons\n0,0,0,0,1,0,0,0,0\n0.001,0,zero,0,1,0,0,0,0\n");
  EXPECT_EQ(parseDeviceStream(badNumber, "b.csv").error, "b.csv:3: column 'y': expected a number, got 'zero'");
  std::stringstream backwards("t,x,y,z,qw,qx,qy,qz,buttons\n0.5,0,0,0,1,0,0,0,0\n0.1,0,0,0,1,0,0,0,0\n");
  EXPECT_NE(parseDeviceStream(backwards, "c.csv").error.find("c.csv:3: column 't': times must increase"),
            std::string::npos);
  std::stringstream short_("t,x,y,z,qw,qx,qy,qz,buttons\n0,0,0\n");
  EXPECT_NE(parseDeviceStream(short_, "d.csv").error.find("d.csv:2: expected 9 columns"), std::string::npos);
}

}  // namespace
}  // namespace trephine
