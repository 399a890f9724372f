#include "framework/core/Lifecycle.h"

#include <cmath>

#include "framework/core/Component.h"

namespace trephine {

uint64_t RunPlan::callsAt(double rateHz) const {
  if (rateHz <= 0 || duration <= 0) return 0;
  // Calls happen at k / rate for k = 0, 1, ... while k / rate < duration. The
  // small tolerance makes 1 s at 3030 Hz give 3030 calls despite rounding.
  const double exact = duration * rateHz;
  const double nearest = std::round(exact);
  const double calls = std::abs(exact - nearest) < 1e-9 * std::max(1.0, exact) ? nearest : std::ceil(exact);
  return static_cast<uint64_t>(calls);
}

void FinishContext::addOutput(const Component& component, std::string fileName) {
  m_outputs.push_back({component.path(), std::move(fileName)});
}

void FinishContext::error(const Component& component, std::string message) {
  m_errors.push_back(component.path() + ": " + message);
}

}  // namespace trephine
