#pragma once
// Gathers the settings of a study (settings/NNN/ and poses.csv) into
// study.csv (a row per setting) and study.md (the same as a table).
// Accuracy: at every study pose, the penetration and normal of the setting's
// target against the reference: the exact contact when the target has an
// exact shape (a phantom), else the reference setting's own answer.
#include <filesystem>
#include <string>
#include <vector>

#include "framework/study/StudyPlan.h"

namespace trephine::study {

struct StudyRow {
  StudySetting setting;
  std::string error;  // empty when the setting ran
  bool isReference = false;
  int poses = 0, comparedPoses = 0, contactMismatches = 0;
  double penetrationErrorP50 = 0, penetrationErrorP99 = 0, penetrationErrorMax = 0;  // mm
  double normalErrorP50 = 0, normalErrorP99 = 0;                                     // deg
  double queryP50 = 0, queryP99 = 0;                                                 // µs per target query
  double broadP50 = 0, narrowP50 = 0;  // µs: the broad phase alone, the rest of the query (NaN if not split)
  double candidatesP50 = 0;            // candidates of the broad phase (points in bone, triangles in reach)
  std::vector<std::pair<std::string, std::string>> run;  // result.csv, column by column
  bool pareto = false;
  double runValue(const std::string& column) const;  // NaN when absent
};

struct StudyReport {
  std::string reference;  // "exact shape" or "setting N (label)"
  std::vector<StudyRow> rows;
};

// Reads what the settings wrote; throws std::runtime_error naming the file
// when poses.csv or the reference's probe is missing or malformed.
StudyReport gatherStudy(const std::filesystem::path& out, const std::vector<StudySetting>& settings,
                        int referenceIndex);

// Writes study.csv and study.md into `out`; returns their names.
std::vector<std::string> writeStudy(const StudyReport& report, const std::filesystem::path& out,
                                    const std::string& scene);

}  // namespace trephine::study
