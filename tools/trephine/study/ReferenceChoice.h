#pragma once
// Which setting of a study is the reference where a target has no exact
// shape: the one that resolves every target and tool finest (the targets'
// voxels or tetrahedra, the tools' shell spacing). Against a coarser one the
// finer settings' accuracy would be measured by the coarser's own error.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "tools/trephine/study/StudyPlan.h"
#include "tools/trephine/study/StudySetting.h"

namespace trephine::study {

// What a setting resolves, from its scene loaded and initialised (not run).
struct SettingResolution {
  bool loaded = false;      // false: not loaded (it does not load, and its run will say why; or not needed)
  std::string loadError;    // why, when it does not
  bool exactEverywhere = false;  // every target has an exact shape and every tool is a sphere
  // mm, per target ("voxels of /patient/skull") and per tool ("shell of /tool/burr").
  std::vector<std::pair<std::string, double>> sizes;
};

SettingResolution describeSetting(const StudyOptions& options, const StudySetting& setting);

// A description as a file, so that each setting is loaded in a process of its
// own (a setting whose load crashes ends only that process): lines of
// tab-separated fields, "loaded 1|0", "exact 1|0", "size NAME MM", "error TEXT".
void writeSettingResolution(const SettingResolution& resolution, const std::filesystem::path& file);
// What the file says; not loaded, with the reason, when it is missing or unreadable.
SettingResolution readSettingResolution(const std::filesystem::path& file);

struct ReferenceChoice {
  int index = 0;
  std::string reason;  // for the report: "the finest: voxels of /patient/skull 0.5 mm"
  std::string error;   // non-empty: the study is refused, and why
};

// `asked`: --reference K (0-based), if given; `allowCoarser`: --coarse-reference.
ReferenceChoice chooseReference(const std::vector<StudySetting>& settings,
                                const std::vector<SettingResolution>& resolutions, std::optional<int> asked,
                                bool allowCoarser);

}  // namespace trephine::study
