#include "tools/trephine/study/StudyPlan.h"

#include <algorithm>
#include <cstdio>

namespace trephine::study {

std::vector<std::string> StudySetting::overrides() const {
  std::vector<std::string> result;
  for (const auto& [field, value] : assignments) result.push_back(field + "=" + value);
  return result;
}

std::string StudySetting::label() const {
  std::string result;
  for (const auto& [field, value] : assignments) {
    if (!result.empty()) result += ", ";
    const size_t dot = field.rfind('.');
    result += (dot == std::string::npos ? field : field.substr(dot + 1)) + "=" + value;
  }
  return result;
}

std::string StudySetting::directoryName() const {
  char name[32];
  std::snprintf(name, sizeof name, "settings/%03d", index + 1);
  return name;
}

std::optional<StudyVariation> parseVariation(const std::string& text, std::string& error) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    error = "--vary expects path.field=v1,v2,..., got '" + text + "'";
    return std::nullopt;
  }
  StudyVariation variation;
  variation.field = text.substr(0, eq);
  if (variation.field.find('.') == std::string::npos) {
    error = "--vary '" + text + "': the field must be written path.field (e.g. /patient/skull.backend)";
    return std::nullopt;
  }
  const std::string values = text.substr(eq + 1);
  size_t start = 0;
  while (start <= values.size()) {
    const size_t comma = std::min(values.find(',', start), values.size());
    const std::string value = values.substr(start, comma - start);
    if (value.empty()) {
      error = "--vary '" + text + "': empty value";
      return std::nullopt;
    }
    if (std::find(variation.values.begin(), variation.values.end(), value) != variation.values.end()) {
      error = "--vary '" + text + "': value '" + value + "' given twice";
      return std::nullopt;
    }
    variation.values.push_back(value);
    start = comma + 1;
  }
  return variation;
}

std::vector<StudySetting> expandSettings(const std::vector<StudyVariation>& variations) {
  std::vector<StudySetting> settings(1);
  for (const StudyVariation& variation : variations) {
    std::vector<StudySetting> next;
    for (const StudySetting& base : settings)
      for (const std::string& value : variation.values) {
        StudySetting setting = base;
        setting.assignments.emplace_back(variation.field, value);
        next.push_back(std::move(setting));
      }
    settings = std::move(next);
  }
  for (size_t i = 0; i < settings.size(); ++i) settings[i].index = static_cast<int>(i);
  return settings;
}

}  // namespace trephine::study
