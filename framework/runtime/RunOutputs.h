#pragma once
// The files of a run (the contract other tools read): summary.json,
// trace.csv (one row per haptic frame; every other tool's trace.PATH.csv) and
// timings.csv (one row per call).
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "framework/logs/HapticFrameLog.h"

namespace trephine {

class Simulation;
class FinishContext;

inline constexpr const char* kTraceHeader =
    "t,device_x,device_y,device_z,proxy_x,proxy_y,proxy_z,force_x,force_y,force_z,penetration,normal_x,normal_y,"
    "normal_z,contacts,penetration_raw,primitives,proxy_inside,removed";

// Writes the three files into `directory`, each whole or not at all; returns
// the names written. A file that cannot be written (no space left) is an
// error in `finish`, listed in summary.json when that one can be written.
std::vector<std::string> writeRunOutputs(const Simulation& simulation, FinishContext& finish,
                                         const std::filesystem::path& directory);

void writeSummaryJson(const Simulation& simulation, const FinishContext* finish, std::ostream& out);
void writeTraceCsv(const Simulation& simulation, std::ostream& out);  // trace.csv's tool
void writeTraceCsv(const HapticFrameLog& log, std::ostream& out);
void writeTimingsCsv(const Simulation& simulation, std::ostream& out);

// The human summary printed by `trephine run`.
void printRunSummary(const Simulation& simulation, std::ostream& out);

}  // namespace trephine
