// libFuzzer target: arbitrary bytes as a device stream file (the CSV that
// ReplayDevice reads and every run records). Any crash, sanitizer report or
// hang is a reader bug; bad input must end in a message naming the line.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "framework/devices/DeviceStream.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  const trephine::DeviceStreamReadResult result = trephine::parseDeviceStream(in, "fuzz.csv");
  // Either samples or an error that says where, never both, never neither.
  if (result.samples.empty() == result.error.empty()) __builtin_trap();
  if (!result.error.empty() && result.error.rfind("fuzz.csv:", 0) != 0) __builtin_trap();
  // Accepted samples have strictly increasing, finite times.
  for (size_t i = 1; i < result.samples.size(); ++i)
    if (!(result.samples[i].t > result.samples[i - 1].t)) __builtin_trap();
  return 0;
}
