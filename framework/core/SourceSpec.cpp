#include "framework/core/SourceSpec.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace trephine {

std::pair<std::string, std::string> SourceSpec::split(const std::string& specification) {
  const size_t mark = specification.find('?');
  if (mark == std::string::npos) return {specification, ""};
  return {specification.substr(0, mark), specification.substr(mark + 1)};
}

SourceSpec::SourceSpec(const std::string& name, const std::string& query, std::map<std::string, double> defaults)
    : m_name(name), m_values(std::move(defaults)) {
  std::stringstream stream(query);
  std::string pair;
  while (std::getline(stream, pair, '&')) {
    if (pair.empty()) continue;
    const size_t eq = pair.find('=');
    const std::string key = pair.substr(0, eq);
    if (!m_values.count(key)) {
      std::string known;
      for (const auto& [k, v] : m_values) known += (known.empty() ? "" : ", ") + k;
      throw std::invalid_argument("phantom '" + name + "' has no key '" + key + "' (keys: " + known + ")");
    }
    if (eq == std::string::npos)
      throw std::invalid_argument("phantom key '" + key + "' needs a value (" + key + "=...)");
    const std::string text = pair.substr(eq + 1);
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || text.empty() || !std::isfinite(value))
      throw std::invalid_argument("phantom key '" + key + "': '" + text + "' is not a number");
    m_values[key] = value;
  }
}

double SourceSpec::positive(const std::string& key) const {
  const double v = number(key);
  if (!(v > 0)) throw std::invalid_argument("phantom key '" + key + "' must be > 0");
  return v;
}

int SourceSpec::wholeNumber(const std::string& key, int min, int max) const {
  const double v = number(key);
  if (v != std::floor(v)) throw std::invalid_argument("phantom key '" + key + "' must be a whole number");
  if (v < min || v > max)
    throw std::invalid_argument("phantom key '" + key + "' must be in [" + std::to_string(min) + ", " +
                                std::to_string(max) + "]");
  return int(v);
}

}  // namespace trephine
