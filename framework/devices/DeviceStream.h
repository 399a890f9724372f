#pragma once
// Device stream files: CSV with the header t,x,y,z,qw,qx,qy,qz,buttons (s, mm).
// "nan" and "inf" are allowed as values so that a recorded bad sample replays
// as the same bad sample.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "framework/devices/DeviceSample.h"

namespace trephine {

inline constexpr const char* kDeviceStreamHeader = "t,x,y,z,qw,qx,qy,qz,buttons";

struct DeviceStreamReadResult {
  std::vector<DeviceSample> samples;
  std::string error;  // "file:line: message" when reading failed
};

DeviceStreamReadResult readDeviceStream(const std::filesystem::path& file);
DeviceStreamReadResult parseDeviceStream(std::istream& in, const std::string& fileName);
void writeDeviceStream(std::ostream& out, const std::vector<DeviceSample>& samples, size_t count);

}  // namespace trephine
