#include "framework/core/Lifecycle.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "framework/core/Component.h"

namespace trephine {

std::string toolTraceName(const Component& renderer) {
  std::string name = renderer.path();
  while (!name.empty() && name.front() == '/') name.erase(0, 1);
  for (char& c : name)
    if (c == '/') c = '.';
  return "trace." + name + ".csv";
}

uint64_t RunPlan::callsAt(double rateHz) const {
  if (!(rateHz > 0) || !(duration > 0) || !std::isfinite(rateHz * duration)) return 0;
  // Calls happen at k / rate for k = 0, 1, ... while k / rate < duration. The
  // small tolerance makes 1 s at 3030 Hz give 3030 calls despite rounding.
  const double exact = duration * rateHz;
  const double nearest = std::round(exact);
  const double calls = std::abs(exact - nearest) < 1e-9 * std::max(1.0, exact) ? nearest : std::ceil(exact);
  return static_cast<uint64_t>(calls);
}

std::optional<std::string> FinishContext::checkFileName(const std::string& fileName) {
  static const char* const reserved[] = {"summary.json", "trace.csv", "timings.csv", ".trephine-run"};
  if (fileName.empty() || fileName == "." || fileName == ".." || fileName.find('/') != std::string::npos ||
      fileName.find('\\') != std::string::npos)
    return std::string("it is not a plain file name (a name in the run directory, without directories)");
  if (std::find(std::begin(reserved), std::end(reserved), fileName) != std::end(reserved))
    return std::string("it is one of the run's own files");
  return std::nullopt;
}

bool FinishContext::claimOutput(const Component& component, const std::string& fileName) {
  std::optional<std::string> problem = checkFileName(fileName);
  for (const Output& o : m_outputs)
    if (!problem && o.file == fileName) problem = o.component + " writes it";
  if (problem) {
    error(component, "cannot write '" + fileName + "': " + *problem);
    return false;
  }
  m_outputs.push_back({component.path(), fileName});
  return true;
}

std::string FinishContext::defaultFileName(const std::string& kind, const Component& component) {
  std::string p = component.path();
  for (char& c : p)
    if (c == '/') c = '.';
  return kind + p + ".csv";
}

void FinishContext::error(const Component& component, std::string message) {
  m_errors.push_back(component.path() + ": " + message);
}

void FinishContext::runError(std::string message) { m_errors.push_back(std::move(message)); }

}  // namespace trephine
