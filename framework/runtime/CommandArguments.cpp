#include "framework/runtime/CommandArguments.h"

#include <charconv>
#include <cmath>

namespace trephine::cli {

std::optional<std::string> Arguments::get(const std::string& option) const {
  const auto it = options.find(option);
  if (it == options.end()) return std::nullopt;
  return it->second;
}

std::optional<double> numberOption(const Arguments& a, const std::string& name, double fallback, std::string& error) {
  const auto text = a.get(name);
  if (!text) return fallback;
  double value = 0;
  const auto r = std::from_chars(text->data(), text->data() + text->size(), value);
  if (r.ec != std::errc() || r.ptr != text->data() + text->size() || !std::isfinite(value)) {
    error = name + " takes a number, not '" + *text + "'";
    return std::nullopt;
  }
  return value;
}

}  // namespace trephine::cli
