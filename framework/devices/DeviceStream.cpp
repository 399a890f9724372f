#include "framework/devices/DeviceStream.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <istream>
#include <limits>
#include <ostream>

#include "framework/core/Strings.h"

namespace trephine {

namespace {

bool parseValue(std::string_view text, double& out) {
  text = trim(text);
  if (text == "nan" || text == "-nan" || text == "NaN") {
    out = std::numeric_limits<double>::quiet_NaN();
    return true;
  }
  if (text == "inf" || text == "+inf") {
    out = std::numeric_limits<double>::infinity();
    return true;
  }
  if (text == "-inf") {
    out = -std::numeric_limits<double>::infinity();
    return true;
  }
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  const auto r = std::from_chars(text.data(), text.data() + text.size(), out);
  return !text.empty() && r.ec == std::errc() && r.ptr == text.data() + text.size();
}

constexpr const char* kColumns[] = {"t", "x", "y", "z", "qw", "qx", "qy", "qz", "buttons"};

}  // namespace

DeviceStreamReadResult parseDeviceStream(std::istream& in, const std::string& fileName) {
  DeviceStreamReadResult result;
  std::string line;
  int lineNumber = 0;
  const auto fail = [&](const std::string& message) {
    result.error = fileName + ":" + std::to_string(lineNumber) + ": " + message;
    result.samples.clear();
    return result;
  };
  if (!std::getline(in, line)) {
    lineNumber = 1;
    return fail("empty file; expected the header " + std::string(kDeviceStreamHeader));
  }
  ++lineNumber;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  // A byte order mark (a spreadsheet's UTF-8 export) shows as nothing: skipped, not reported as a header typo.
  if (line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);
  if (trim(line) != kDeviceStreamHeader)
    return fail("expected the header " + std::string(kDeviceStreamHeader) + ", got " + visiblyQuoted(line));
  double previousT = -std::numeric_limits<double>::infinity();
  while (std::getline(in, line)) {
    ++lineNumber;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) continue;
    double values[9];
    size_t column = 0, start = 0;
    while (true) {
      const size_t comma = line.find(',', start);
      const std::string_view cell =
          std::string_view(line).substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (column >= 9) return fail("more than 9 columns");
      if (!parseValue(cell, values[column]))
        return fail("column '" + std::string(kColumns[column]) + "': expected a number, got " + visiblyQuoted(cell));
      ++column;
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (column != 9)
      return fail("expected 9 columns (" + std::string(kDeviceStreamHeader) + "), got " + std::to_string(column));
    if (!std::isfinite(values[0])) return fail("column 't': time must be finite");
    if (values[0] <= previousT)
      return fail("column 't': times must increase (got " + formatDouble(values[0]) + " after " +
                  formatDouble(previousT) + ")");
    if (!(values[8] >= 0 && values[8] <= 4294967295.0 && values[8] == std::floor(values[8])))
      return fail("column 'buttons': expected a non-negative integer bit mask");
    previousT = values[0];
    DeviceSample s;
    s.t = values[0];
    s.position = Vec3(values[1], values[2], values[3]);
    s.orientation = Quat(values[4], values[5], values[6], values[7]);
    s.buttons = static_cast<uint32_t>(values[8]);
    result.samples.push_back(s);
  }
  if (result.samples.empty()) return fail("no samples after the header");
  return result;
}

DeviceStreamReadResult readDeviceStream(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) {
    DeviceStreamReadResult r;
    r.error = file.string() + ": cannot open";
    return r;
  }
  return parseDeviceStream(in, file.string());
}

void writeDeviceStream(std::ostream& out, const std::vector<DeviceSample>& samples, size_t count) {
  out << kDeviceStreamHeader << "\n";
  std::string row;
  for (size_t i = 0; i < count && i < samples.size(); ++i) {
    const DeviceSample& s = samples[i];
    row = formatDouble(s.t);
    for (int k = 0; k < 3; ++k) row += "," + formatDouble(s.position[k]);
    row += "," + formatDouble(s.orientation.w()) + "," + formatDouble(s.orientation.x()) + "," +
           formatDouble(s.orientation.y()) + "," + formatDouble(s.orientation.z());
    row += "," + std::to_string(s.buttons) + "\n";
    out << row;
  }
}

}  // namespace trephine
