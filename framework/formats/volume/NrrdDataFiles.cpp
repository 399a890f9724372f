#include "framework/formats/volume/NrrdDataFiles.h"

#include <algorithm>
#include <cstdint>

#include "framework/core/Strings.h"
#include "framework/formats/volume/HeaderText.h"
#include "framework/formats/volume/VolumeReader.h"

namespace trephine::formats {

std::optional<std::string> formatSeriesName(std::string_view format, int64_t number) {
  std::string out;
  bool converted = false;
  for (size_t n = 0; n < format.size(); ++n) {
    if (format[n] != '%') {
      out += format[n];
      continue;
    }
    if (++n >= format.size()) return std::nullopt;
    if (format[n] == '%') {
      out += '%';
      continue;
    }
    if (converted) return std::nullopt;  // a second conversion has no argument
    bool zeroPad = false, leftAlign = false, plus = false, space = false;
    for (; n < format.size(); ++n) {
      const char flag = format[n];
      if (flag == '0')
        zeroPad = true;
      else if (flag == '-')
        leftAlign = true;
      else if (flag == '+')
        plus = true;
      else if (flag == ' ')
        space = true;
      else
        break;
    }
    size_t width = 0;
    for (; n < format.size() && format[n] >= '0' && format[n] <= '9'; ++n) {
      width = width * 10 + size_t(format[n] - '0');
      if (width > 64) return std::nullopt;
    }
    if (n >= format.size() || (format[n] != 'd' && format[n] != 'i' && format[n] != 'u')) return std::nullopt;
    if (format[n] == 'u' && number < 0) return std::nullopt;
    std::string digits = std::to_string(number < 0 ? -(number + 1) + uint64_t(1) : uint64_t(number));
    std::string sign = number < 0 ? "-" : (plus ? "+" : (space ? " " : ""));
    if (format[n] == 'u') sign.clear();
    const size_t length = sign.size() + digits.size();
    if (length < width) {
      if (leftAlign)
        digits += std::string(width - length, ' ');
      else if (zeroPad)
        digits.insert(0, std::string(width - length, '0'));
      else
        sign.insert(0, std::string(width - length, ' '));
    }
    out += sign + digits;
    converted = true;
  }
  if (!converted) return std::nullopt;
  return out;
}

NrrdDataFiles expandNrrdDataFile(std::string_view value, const std::filesystem::path& header, uint64_t maxFiles) {
  const std::filesystem::path directory = header.parent_path();
  const std::vector<std::string_view> words = splitWhitespace(value);
  NrrdDataFiles result;
  const bool series = (words.size() == 4 || words.size() == 5) && words[0].find('%') != std::string_view::npos;
  if (!series) {
    if (!isPlainFileName(value))
      throw VolumeReadError(header, "data file " + quoteForMessage(value) + " is not a file name");
    result.files.push_back(directory / std::string(value));
    return result;
  }
  std::optional<int64_t> numbers[4];
  for (size_t n = 1; n < words.size(); ++n) numbers[n - 1] = parseInteger(words[n]);
  const auto fail = [&](const std::string& problem) -> VolumeReadError {
    return VolumeReadError(header, "data file " + quoteForMessage(value) + ": " + problem);
  };
  if (!numbers[0] || !numbers[1] || !numbers[2] || (words.size() == 5 && !numbers[3]))
    throw fail("expected '<format> <first> <last> <step> [<slab dimension>]' with integer numbers");
  const int64_t first = *numbers[0], last = *numbers[1], step = *numbers[2];
  if (step == 0) throw fail("the step is 0");
  if ((last - static_cast<__int128>(first)) * step < 0) throw fail("the step goes away from the last number");
  const __int128 count = (static_cast<__int128>(last) - first) / step + 1;
  if (count > static_cast<__int128>(maxFiles))
    throw fail("names " + std::to_string(static_cast<long long>(std::min<__int128>(count, INT64_MAX))) +
               " files, more than the " + std::to_string(maxFiles) + " the sizes allow");
  if (words.size() == 5) result.slabDimension = *numbers[3];
  for (int64_t n = 0; n < static_cast<int64_t>(count); ++n) {
    const std::optional<std::string> name =
        formatSeriesName(words[0], static_cast<int64_t>(first + static_cast<__int128>(n) * step));
    if (!name || !isPlainFileName(*name))
      throw fail("the format must hold exactly one %d, %i or %u conversion (with optional 0 flag and width)");
    result.files.push_back(directory / *name);
  }
  return result;
}

}  // namespace trephine::formats
