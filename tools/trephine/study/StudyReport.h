#pragma once
// Gathers the settings of a study (settings/NNN/ and poses.csv) into
// study.csv (a row per setting) and study.md (the same as a table).
// Accuracy, for every tool and target that touched (a pair): at each of the
// pair's poses, the penetration and normal of the setting's target against
// the reference: the exact contact when the tool is a sphere (a phantom's
// closed form, a scan's interpolated isosurface, a mesh's boundary
// triangles), else the reference setting's own answer; and, beside it, the
// agreement with the reference setting.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "tools/trephine/study/StudyPlan.h"

namespace trephine::study {

// A setting's accuracy for one tool on one target, at that pair's poses.
struct PairAccuracy {
  int poses = 0, comparedPoses = 0, contactMismatches = 0;
  double penetrationErrorP50 = 0, penetrationErrorP99 = 0, penetrationErrorMax = 0;  // mm
  double normalErrorP50 = 0, normalErrorP99 = 0;                                     // deg
  // Penetration disagreement with the reference setting's answers (p99), whatever the reference is.
  double agreementP99 = std::nan("");  // mm
  // The closed loop of the pair's force renderer in the setting's run (tools.csv).
  double forceStepP99 = std::nan(""), unexplainedStepP99 = std::nan("");  // N
  double proxyInsideFrames = std::nan(""), nanFrames = std::nan("");
};

// A tool and a target that touched in the reference's run, and what its
// accuracy is measured against.
struct StudiedPair {
  std::string tool, target;  // component paths
  std::string renderer;      // the force renderer whose frames gave the poses
  bool exact = false;        // against the exact shape, else the reference setting
  std::string reference;     // "the exact shape of the phantom" or "setting N (label): why"
};

struct StudyRow : PairAccuracy {  // the accuracy of the studied pair (the first)
  StudySetting setting;
  std::string error;  // empty when the setting ran
  bool isReference = false;
  std::vector<PairAccuracy> pairs;  // one per StudyReport::pairs
  double queryP50 = 0, queryP99 = 0;                                                 // µs per target query
  double broadP50 = 0, narrowP50 = 0;  // µs: the broad phase alone, the rest of the query (NaN if not split)
  double candidatesP50 = 0;            // candidates of the broad phase (points in bone, triangles in reach)
  std::vector<std::pair<std::string, std::string>> run;  // result.csv, column by column
  bool pareto = false;
  double runValue(const std::string& column) const;  // NaN when absent
};

struct StudyReport {
  int repeat = 1;  // runs of each setting asked for
  std::string reference;  // the studied pair's (the first): "the exact shape ..." or "setting N (label): why"
  std::vector<StudiedPair> pairs;
  std::vector<StudyRow> rows;
};

// Reads what the settings wrote; throws std::runtime_error naming the file
// when poses.csv is missing or malformed. `referenceChoice`: why the
// reference setting is the one it is (for the report), e.g. "the finest".
// `repeat`: the runs of each setting; its step p50 and p99 are the medians
// over them (the first run's result.csv and timing-R.csv for the rest).
StudyReport gatherStudy(const std::filesystem::path& out, const std::vector<StudySetting>& settings,
                        int referenceIndex, const std::string& referenceChoice = "", int repeat = 1);

// Writes study.csv (the studied pair's accuracy), pairs.csv (a row per
// setting and pair) and study.md into `out`; returns their names.
std::vector<std::string> writeStudy(const StudyReport& report, const std::filesystem::path& out,
                                    const std::string& scene);

}  // namespace trephine::study
