#pragma once
// The settings of a study: the cartesian product of the values given to each
// varied field (`--vary path.field=v1,v2,...`), the first field varying
// slowest. Setting k runs the scene with one `--set path.field=value` per
// varied field on top of the study's own --set overrides.
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace trephine::study {

struct StudyVariation {
  std::string field;                // "/patient/skull.backend"
  std::vector<std::string> values;  // in the order given
};

struct StudySetting {
  int index = 0;                                                 // 0-based, in product order
  std::vector<std::pair<std::string, std::string>> assignments;  // field, value (one per variation)

  // "--set" values of this setting.
  std::vector<std::string> overrides() const;
  // "backend=embree, file=phantom:skull?voxel=1" (the fields' last path element).
  std::string label() const;
  // Directory of its run under the study's output: settings/007.
  std::string directoryName() const;
};

// Parses "path.field=v1,v2,..."; returns nullopt and sets `error` when the
// field has no '.', a value is empty or repeated, or there is no value.
std::optional<StudyVariation> parseVariation(const std::string& text, std::string& error);

std::vector<StudySetting> expandSettings(const std::vector<StudyVariation>& variations);

}  // namespace trephine::study
