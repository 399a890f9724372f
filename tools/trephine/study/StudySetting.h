#pragma once
// One setting of a study, run in this process: the scene with the setting's
// overrides is loaded, its collision target queried at the study's tool poses
// (before anything is drilled or deformed), then run; everything is written
// under the study's directory, in settings/NNN/:
//   summary.json, trace.csv, timings.csv  the run, as `trephine run` writes them
//   probe.csv    per pose: the target's penetration and normal, query time
//   result.csv   one row: closed-loop figures and time per frame of the run
//   error.txt    instead of result.csv when the setting cannot be loaded or run
// The reference setting runs first and also writes poses.csv at the top of the
// study's directory: for every tool and target that touched in its run, tool
// positions from their frames in contact, with the exact contact at each when
// the target has an exact shape and the tool is a sphere.
#include <filesystem>
#include <string>

#include "framework/runtime/Simulation.h"
#include "tools/trephine/study/StudyPlan.h"

namespace trephine::study {

struct StudyOptions {
  std::filesystem::path scene;
  std::filesystem::path out;
  SimulationOptions simulation;  // duration, seed and the study's own --set overrides
  std::string target;            // path of the one target to study; empty: every target a tool touched
  int referenceIndex = 0;        // setting whose run gives the poses (and the reference without an exact shape)
  int posesPerKind = 200;        // proxy poses and as many device poses, evenly over the contact frames
  // Which study this is: every rank of one study has the same, and writes it
  // into poses.csv, result.csv and error.txt, so files an earlier study left
  // in the same folder are never taken for this one's.
  std::string studyId;
};

// The study `file` (poses.csv or result.csv: the `study` column of its first
// row; error.txt: its first line, "study ID") belongs to, or "" when it is
// missing or says none.
std::string studyOfFile(const std::filesystem::path& file);
// The message of an error.txt, without its first line.
std::string settingErrorMessage(const std::filesystem::path& file);

inline constexpr const char* kPosesFile = "poses.csv";
inline constexpr const char* kProbeFile = "probe.csv";
// The reference run's device input, replayed by every other setting:
// motion.<device path with / as .>.csv in the study's folder.
inline constexpr const char* kMotionFilePrefix = "motion";
// And its simulated duration, which the other settings run for too.
inline constexpr const char* kMotionDurationFile = "motion_duration.csv";
// And the times a device took a sample without its jump test (device,t,study).
inline constexpr const char* kMotionResetsFile = "motion_resets.csv";
// Written by the reference's run when a tool and target it studies have no
// exact contact: a line "TOOL on TARGET: why" for each such pair.
inline constexpr const char* kNoExactShapeFile = "no_exact_shape.txt";
// Written by the reference's run for the pairs it has an exact contact for:
// a line "TOOL on TARGET: what the reference is" for each.
inline constexpr const char* kReferencesFile = "references.txt";
inline constexpr const char* kResultFile = "result.csv";
// Every tool's closed-loop figures in a setting's run, a row per force renderer.
inline constexpr const char* kToolsFile = "tools.csv";
// timing-R.csv: the R-th run (R >= 2) of a setting, timed only.
std::filesystem::path timingFile(const std::filesystem::path& settingDirectory, int run);
inline constexpr const char* kErrorFile = "error.txt";

// Returns true when the setting ran to completion and its files are written;
// otherwise error.txt says why.
bool runStudySetting(const StudyOptions& options, const StudySetting& setting);
// The `run`-th run of a setting (run >= 2), after its first succeeded:
// loaded fresh, on the reference's motion, timed only (nothing of the run is
// written but timing-R.csv: complete, step p50 and p99, wall time, or why it
// failed). Returns whether it completed.
bool runTimingRun(const StudyOptions& options, const StudySetting& setting, int run);
// Writes timing-R.csv of a run that failed, with why.
void writeTimingFailure(const std::filesystem::path& directory, int run, const std::string& studyId,
                        const std::string& why);

// The folder of `setting` in the study's `out`, made when missing and
// reached without following a link (a `settings/002` planted as a link to
// elsewhere is refused). Throws FileWriteError naming what is in the way.
std::filesystem::path settingFolder(const std::filesystem::path& out, const StudySetting& setting);
// What is in the way of that folder without making it: a link, a file or a
// special file where a folder of the study's goes; "" when nothing is.
std::string settingFolderProblem(const std::filesystem::path& out, const StudySetting& setting);

// Writes error.txt of a setting whole (other processes wait for it).
void writeSettingError(const std::filesystem::path& directory, const std::string& studyId, const std::string& message);

}  // namespace trephine::study
