#include "tools/trephine/study/StudyReport.h"

#include <sys/utsname.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "framework/core/AtomicFile.h"
#include "framework/math/Math.h"
#include "tools/trephine/study/StudySetting.h"
#include "tools/trephine/study/StudyTable.h"

namespace trephine::study {

namespace {

constexpr double kMismatchDepth = 0.1;  // mm

// One contact answer at a pose.
struct Answer {
  double penetration = 0;  // mm, 0 without contact
  Vec3 normal = Vec3::Zero();
};

std::vector<Answer> readAnswers(const std::filesystem::path& file, const char* penetration, const char* nx,
                                const char* ny, const char* nz) {
  const Table table = readTable(file);
  const size_t p = column(table, penetration, file), x = column(table, nx, file), y = column(table, ny, file),
               z = column(table, nz, file);
  std::vector<Answer> answers;
  for (size_t r = 1; r < table.size(); ++r)
    answers.push_back(
        {toNumber(table[r][p]), Vec3(toNumber(table[r][x]), toNumber(table[r][y]), toNumber(table[r][z]))});
  return answers;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  // Nearest rank: the smallest value with at least a fraction q at or below it.
  const double rank = std::ceil(q * static_cast<double>(values.size()));
  return values[std::clamp<size_t>(static_cast<size_t>(std::max(rank, 1.0)) - 1, 0, values.size() - 1)];
}

// The accuracy at the poses `indices` (rows of poses.csv).
void compare(PairAccuracy& row, const std::vector<Answer>& measured, const std::vector<Answer>& reference,
             const std::vector<size_t>& indices) {
  std::vector<double> penetrationErrors, normalErrors;
  for (const size_t i : indices) {
    if (i >= measured.size()) continue;
    ++row.poses;
    if (i >= reference.size()) continue;  // no reference to compare with
    const Answer& m = measured[i];
    const Answer& r = reference[i];
    const bool inM = m.penetration > 0, inR = r.penetration > 0;
    if (!inM && !inR) continue;  // neither touches: nothing to compare
    ++row.comparedPoses;
    // A contact one side misses by more than kMismatchDepth (a pose right at
    // the surface is in contact or not by a hair: no mismatch).
    if (std::abs(m.penetration - r.penetration) > kMismatchDepth && (!inM || !inR)) ++row.contactMismatches;
    penetrationErrors.push_back(std::abs(m.penetration - r.penetration));
    if (inM && inR && m.normal.norm() > 0.5 && r.normal.norm() > 0.5) {
      const double c = std::clamp(m.normal.normalized().dot(r.normal.normalized()), -1.0, 1.0);
      normalErrors.push_back(std::acos(c) * 180.0 / std::numbers::pi);
    }
  }
  row.penetrationErrorP50 = percentile(penetrationErrors, 0.5);
  row.penetrationErrorP99 = percentile(penetrationErrors, 0.99);
  row.penetrationErrorMax =
      penetrationErrors.empty() ? std::nan("") : *std::max_element(penetrationErrors.begin(), penetrationErrors.end());
  row.normalErrorP50 = percentile(normalErrors, 0.5);
  row.normalErrorP99 = percentile(normalErrors, 0.99);
}

// Time per frame (median) against penetration error (p99): a setting is on
// the front when no other is at least as good in both and better in one.
// A reference setting without an exact shape has no error by definition: it
// takes no part.
void markPareto(std::vector<StudyRow>& rows, bool referenceIsExact) {
  const auto competes = [&](const StudyRow& row) {
    return row.error.empty() && (referenceIsExact || !row.isReference);
  };
  for (StudyRow& a : rows) {
    const double ta = a.runValue("step_p50_us"), ea = a.penetrationErrorP99;
    a.pareto = competes(a) && std::isfinite(ta) && std::isfinite(ea);
    if (!a.pareto) continue;
    for (const StudyRow& b : rows) {
      if (&a == &b || !competes(b)) continue;
      const double tb = b.runValue("step_p50_us"), eb = b.penetrationErrorP99;
      if (tb <= ta && eb <= ea && (tb < ta || eb < ea)) a.pareto = false;
    }
  }
}

std::string format(double value, int digits) {
  if (!std::isfinite(value)) return "-";
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(digits);
  s << value;
  return s.str();
}

std::string csvQuoted(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return quoted + "\"";
}

// The processor, its cores, the system and the build, for study.md.
std::string machineDescription() {
  std::string model = "an unknown processor";
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  std::ostringstream text;
  text << model << ", " << std::thread::hardware_concurrency() << " logical cores";
  utsname system{};
  if (uname(&system) == 0) text << ", " << system.sysname << " " << system.release;
  text << "; trephine built " << TREPHINE_BUILD_TYPE << " by "
#if defined(__clang__)
       << "clang " << __clang_version__;
#elif defined(__GNUC__)
       << "GCC " << __VERSION__;
#else
       << "an unknown compiler";
#endif
  return text.str();
}

// The closed-loop figures of `renderer` from a setting's tools.csv (left NaN
// when the file or the renderer is missing).
void addClosedLoop(PairAccuracy& pair, const std::filesystem::path& file, const std::string& renderer) {
  if (!std::filesystem::is_regular_file(file)) return;
  const Table tools = readTable(file);
  const size_t who = column(tools, "renderer", file);
  for (size_t r = 1; r < tools.size(); ++r) {
    if (tools[r][who] != renderer) continue;
    pair.forceStepP99 = toNumber(tools[r][column(tools, "force_step_p99_N", file)]);
    pair.unexplainedStepP99 = toNumber(tools[r][column(tools, "unexplained_step_p99_N", file)]);
    pair.proxyInsideFrames = toNumber(tools[r][column(tools, "proxy_inside_frames", file)]);
    pair.nanFrames = toNumber(tools[r][column(tools, "nan_frames", file)]);
  }
}

void setRunValue(StudyRow& row, const std::string& key, double value) {
  for (auto& [name, text] : row.run)
    if (name == key) {
      text = format(value, 6);
      return;
    }
  row.run.emplace_back(key, format(value, 6));
}

double median(std::vector<double> values) { return percentile(std::move(values), 0.5); }

// The step p50 and p99 of the row become the medians over its runs (the
// first, then each timing-R.csv that completed); the spread of the p50 and
// the count of runs are kept beside them.
void combineTimingRuns(StudyRow& row, const std::filesystem::path& directory, int repeat) {
  std::vector<double> p50s = {row.runValue("step_p50_us")}, p99s = {row.runValue("step_p99_us")};
  for (int run = 2; run <= repeat; ++run) {
    const std::filesystem::path file = timingFile(directory, run);
    if (!std::filesystem::is_regular_file(file)) continue;
    const Table timing = readTable(file);
    if (timing.size() != 2 || toNumber(timing[1][column(timing, "complete", file)]) != 1) continue;
    p50s.push_back(toNumber(timing[1][column(timing, "step_p50_us", file)]));
    p99s.push_back(toNumber(timing[1][column(timing, "step_p99_us", file)]));
  }
  setRunValue(row, "first_run_step_p50_us", p50s.front());
  setRunValue(row, "step_p50_us", median(p50s));
  setRunValue(row, "step_p99_us", median(p99s));
  setRunValue(row, "step_p50_min_us", *std::min_element(p50s.begin(), p50s.end()));
  setRunValue(row, "step_p50_max_us", *std::max_element(p50s.begin(), p50s.end()));
  setRunValue(row, "timing_runs", double(p50s.size()));
}

}  // namespace

double StudyRow::runValue(const std::string& name) const {
  for (const auto& [key, value] : run)
    if (key == name) return toNumber(value);
  return std::nan("");
}

StudyReport gatherStudy(const std::filesystem::path& out, const std::vector<StudySetting>& settings, int referenceIndex,
                        const std::string& referenceChoice, int repeat) {
  StudyReport report;
  report.repeat = repeat;
  const std::filesystem::path posesFile = out / kPosesFile;
  const Table poses = readTable(posesFile);
  const size_t toolColumn = column(poses, "tool", posesFile), targetColumn = column(poses, "target", posesFile),
               rendererColumn = column(poses, "renderer", posesFile);
  const std::vector<Answer> exact = readAnswers(posesFile, "exact_penetration", "exact_nx", "exact_ny", "exact_nz");
  // The pairs in the order of poses.csv (the studied one first), and their rows.
  std::vector<std::vector<size_t>> rowsOfPair;
  for (size_t r = 1; r < poses.size(); ++r) {
    const std::string &tool = poses[r][toolColumn], &target = poses[r][targetColumn];
    size_t p = 0;
    while (p < report.pairs.size() && !(report.pairs[p].tool == tool && report.pairs[p].target == target)) ++p;
    if (p == report.pairs.size())
      report.pairs.push_back({tool, target, poses[r][rendererColumn], true, ""}), rowsOfPair.emplace_back();
    rowsOfPair[p].push_back(r - 1);
  }
  if (report.pairs.empty()) throw std::runtime_error(posesFile.string() + ": no pose");
  // Why a pair has no exact contact, and what the exact one is: "TOOL on TARGET: text" lines.
  const auto readLines = [](const std::filesystem::path& file) {
    std::vector<std::string> lines;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  };
  const std::vector<std::string> whyLines = readLines(out / kNoExactShapeFile);
  const std::vector<std::string> referenceLines = readLines(out / kReferencesFile);
  const StudySetting& referenceSetting = settings.at(static_cast<size_t>(referenceIndex));
  // The reference setting's own answers: the reference of a pair without an
  // exact contact, and what every setting's agreement is measured against.
  std::vector<Answer> settingReference;
  std::string unreadable;
  try {
    settingReference =
        readAnswers(out / referenceSetting.directoryName() / kProbeFile, "penetration", "nx", "ny", "nz");
  } catch (const std::exception& e) {
    // The other settings' rows are still worth having (their time, their
    // closed loop); their accuracy against it is unknown.
    unreadable = "; its answers cannot be read (" + std::string(e.what()) + "), so no error is measured";
  }
  for (size_t p = 0; p < report.pairs.size(); ++p) {
    StudiedPair& pair = report.pairs[p];
    for (const size_t i : rowsOfPair[p]) pair.exact = pair.exact && std::isfinite(exact[i].penetration);
    const std::string prefix = pair.tool + " on " + pair.target + ": ";
    if (pair.exact) {
      pair.reference = "the exact shape of the phantom";
      for (const std::string& line : referenceLines)
        if (line.rfind(prefix, 0) == 0) pair.reference = line.substr(prefix.size());
      continue;
    }
    std::string why;
    for (const std::string& line : whyLines)
      if (line.rfind(prefix, 0) == 0) why = line.substr(prefix.size());
    pair.reference = "setting " + std::to_string(referenceIndex + 1) + " (" + referenceSetting.label() + ")" +
                     (referenceChoice.empty() ? std::string() : ", " + referenceChoice) +
                     ": no exact shape for this target" + (why.empty() ? std::string() : ": " + why);
    pair.reference += unreadable;
  }
  report.reference = report.pairs.front().reference;
  for (const StudySetting& setting : settings) {
    StudyRow row;
    row.setting = setting;
    row.isReference = setting.index == referenceIndex;
    const std::filesystem::path directory = out / setting.directoryName();
    if (std::filesystem::is_regular_file(directory / kErrorFile)) {
      row.error = settingErrorMessage(directory / kErrorFile);
      report.rows.push_back(std::move(row));
      continue;
    }
    try {
      const std::vector<Answer> measured = readAnswers(directory / kProbeFile, "penetration", "nx", "ny", "nz");
      for (size_t p = 0; p < report.pairs.size(); ++p) {
        PairAccuracy accuracy;
        compare(accuracy, measured, report.pairs[p].exact ? exact : settingReference, rowsOfPair[p]);
        PairAccuracy agreement;
        compare(agreement, measured, settingReference, rowsOfPair[p]);
        accuracy.agreementP99 = agreement.penetrationErrorP99;
        addClosedLoop(accuracy, directory / kToolsFile, report.pairs[p].renderer);
        row.pairs.push_back(accuracy);
      }
      static_cast<PairAccuracy&>(row) = row.pairs.front();
      const Table probe = readTable(directory / kProbeFile);
      const size_t q = column(probe, "query_us", directory / kProbeFile);
      const size_t b = column(probe, "broad_us", directory / kProbeFile);
      const size_t c = column(probe, "candidates", directory / kProbeFile);
      std::vector<double> times, broad, narrow, candidates;
      for (size_t r = 1; r < probe.size(); ++r) {
        const double query = toNumber(probe[r][q]), broadUs = toNumber(probe[r][b]);
        times.push_back(query);
        if (!std::isfinite(broadUs)) continue;
        broad.push_back(broadUs);
        narrow.push_back(std::max(0.0, query - broadUs));
        candidates.push_back(toNumber(probe[r][c]));
      }
      row.queryP50 = percentile(times, 0.5);
      row.queryP99 = percentile(times, 0.99);
      row.broadP50 = percentile(broad, 0.5);
      row.narrowP50 = percentile(narrow, 0.5);
      row.candidatesP50 = percentile(candidates, 0.5);
      const Table result = readTable(directory / kResultFile);
      if (result.size() != 2) throw std::runtime_error((directory / kResultFile).string() + ": expected one row");
      for (size_t c = 0; c < result[0].size(); ++c) row.run.emplace_back(result[0][c], result[1][c]);
      combineTimingRuns(row, directory, repeat);
    } catch (const std::exception& e) {
      row.error = e.what();
    }
    report.rows.push_back(std::move(row));
  }
  markPareto(report.rows, report.pairs.front().exact);
  return report;
}

std::vector<std::string> writeStudy(const StudyReport& report, const std::filesystem::path& out,
                                    const std::string& scene) {
  std::vector<std::string> runColumns;
  for (const StudyRow& row : report.rows)
    if (row.error.empty() && !row.run.empty()) {
      for (const auto& [key, value] : row.run) runColumns.push_back(key);
      break;
    }
  std::ostringstream csv;
  csv << "setting,label";
  if (!report.rows.empty())
    for (const auto& [field, value] : report.rows.front().setting.assignments) csv << ',' << csvQuoted(field);
  csv << ",status,reference,exact_reference,tool,target,poses,compared_poses,contact_mismatches,pen_err_p50_mm,pen_err_"
         "p99_mm,pen_err_max_mm,"
         "normal_err_p50_deg,normal_err_p99_deg,agree_ref_p99_mm,query_p50_us,query_p99_us,broad_p50_us,narrow_p50_us,"
         "candidates_p50";
  for (const std::string& c : runColumns) csv << ',' << c;
  csv << ",pareto\n";
  for (const StudyRow& row : report.rows) {
    csv << row.setting.index + 1 << ',' << csvQuoted(row.setting.label());
    for (const auto& [field, value] : row.setting.assignments) csv << ',' << csvQuoted(value);
    csv << ',' << csvQuoted(row.error.empty() ? "ok" : row.error) << ',' << (row.isReference ? 1 : 0) << ','
        << (report.pairs.front().exact ? 1 : 0) << ',' << csvQuoted(report.pairs.front().tool) << ','
        << csvQuoted(report.pairs.front().target) << ',' << row.poses << ',' << row.comparedPoses << ','
        << row.contactMismatches;
    for (double v : {row.penetrationErrorP50, row.penetrationErrorP99, row.penetrationErrorMax, row.normalErrorP50,
                     row.normalErrorP99, row.agreementP99, row.queryP50, row.queryP99, row.broadP50, row.narrowP50,
                     row.candidatesP50})
      csv << ',' << (std::isfinite(v) ? format(v, 6) : "nan");
    for (const std::string& c : runColumns) {
      const double v = row.runValue(c);
      csv << ',' << (std::isfinite(v) ? format(v, 6) : "nan");
    }
    csv << ',' << (row.pareto ? 1 : 0) << '\n';
  }

  // A row per setting and pair.
  std::ostringstream pairsCsv;
  pairsCsv << "setting,label,status,tool,target,exact_reference,poses,compared_poses,contact_mismatches,"
              "pen_err_p50_mm,pen_err_p99_mm,pen_err_max_mm,normal_err_p50_deg,normal_err_p99_deg,agree_ref_p99_mm,"
              "renderer,force_step_p99_N,unexplained_step_p99_N,proxy_inside_frames,nan_frames\n";
  for (const StudyRow& row : report.rows)
    for (size_t p = 0; p < report.pairs.size(); ++p) {
      const StudiedPair& pair = report.pairs[p];
      pairsCsv << row.setting.index + 1 << ',' << csvQuoted(row.setting.label()) << ','
               << csvQuoted(row.error.empty() ? "ok" : row.error) << ',' << csvQuoted(pair.tool) << ','
               << csvQuoted(pair.target) << ',' << (pair.exact ? 1 : 0);
      if (p >= row.pairs.size()) {
        pairsCsv << ",0,0,0,nan,nan,nan,nan,nan,nan," << csvQuoted(pair.renderer) << ",nan,nan,nan,nan\n";
        continue;
      }
      const PairAccuracy& a = row.pairs[p];
      pairsCsv << ',' << a.poses << ',' << a.comparedPoses << ',' << a.contactMismatches;
      for (double v : {a.penetrationErrorP50, a.penetrationErrorP99, a.penetrationErrorMax, a.normalErrorP50,
                       a.normalErrorP99, a.agreementP99})
        pairsCsv << ',' << (std::isfinite(v) ? format(v, 6) : "nan");
      pairsCsv << ',' << csvQuoted(pair.renderer);
      for (double v : {a.forceStepP99, a.unexplainedStepP99, a.proxyInsideFrames, a.nanFrames})
        pairsCsv << ',' << (std::isfinite(v) ? format(v, 6) : "nan");
      pairsCsv << '\n';
    }

  std::ostringstream md;
  int poses = 0;
  for (const StudyRow& row : report.rows) poses = std::max(poses, row.poses);
  md << "# Study of " << scene << "\n\n"
     << "Accuracy of " << report.pairs.front().tool << " on " << report.pairs.front().target << " at " << poses
     << " tool poses (proxy and device positions of the reference setting's frames where they touched), against "
     << report.reference << ". Time: the haptic step of each setting's runs (µs; the medians over " << report.repeat
     << " runs of each setting, interleaved: every setting ran once in each round, the first run with its accuracy "
        "probe, the others timed only; the range is that of the runs' p50) and one target query at the "
     << "poses (µs), split into its broad phase alone (the search for candidates: shell points in bone, triangles in "
        "reach) and the rest. Contact mismatches: poses where one side finds no contact and the other one deeper than "
        "0.1 mm. Compared poses: those where the setting or the reference finds a contact (a pose neither touches "
        "says nothing of accuracy), so their count differs between settings. Agreement: the penetration's p99 "
        "difference from the reference setting's own answers, beside the error against the reference. "
        "Pareto front, one rule for every setting that ran (the reference setting too when the reference is exact; "
        "when the reference is that setting, it has no error by definition and takes no part): a setting is on the "
        "front when no other is at least as fast (step p50) and as accurate (penetration error p99) and better in "
        "one.\n\n"
     << "Machine: " << machineDescription() << ".\n\n"
     << "Motion: every setting runs on the same device input. The reference setting's run reads its devices as "
        "the scene says (a scripted path planned against its own model, a replay, a simulated hand) and its input is "
        "recorded (motion.DEVICE.csv in this folder); every other setting's devices replay that input instead of "
        "their own, sample for sample, so the step times, force steps and removed bone of every row come from one "
        "motion. A device whose motion answers the force (a simulated hand) is replayed open loop in the other "
        "settings, as it moved in the reference's run. A device whose own field the study varies (its path, its "
        "speed) keeps its own input in every setting: its motion is what is compared.\n\n"
     << "| # | setting | pen. error p50 / p99 (mm) | normal error p50 / p99 (deg) | agreement p99 (mm) | contact "
        "mismatches | "
        "step p50 / p99 (p50's range, runs) (µs) | query p50 / p99 (µs) | broad + narrow p50 (µs) | dF p99 / max (N) | "
        "proxy inside | NaN "
        "| "
        "removed | Pareto |\n"
     << "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|\n";
  for (const StudyRow& row : report.rows) {
    md << "| " << row.setting.index + 1 << " | " << row.setting.label() << (row.isReference ? " (reference)" : "")
       << " | ";
    if (!row.error.empty()) {
      std::string oneLine = row.error;
      for (char& c : oneLine)
        if (c == '\n' || c == '|') c = c == '|' ? '/' : ' ';
      md << "failed: " << oneLine << " | | | | | | | | | | | |\n";
      continue;
    }
    md << format(row.penetrationErrorP50, 3) << " / " << format(row.penetrationErrorP99, 3) << " | "
       << format(row.normalErrorP50, 2) << " / " << format(row.normalErrorP99, 2) << " | "
       << format(row.agreementP99, 3) << " | " << row.contactMismatches << " of " << row.comparedPoses << " | "
       << format(row.runValue("step_p50_us"), 1) << " / " << format(row.runValue("step_p99_us"), 1) << " ("
       << format(row.runValue("step_p50_min_us"), 1) << " to " << format(row.runValue("step_p50_max_us"), 1) << ", "
       << format(row.runValue("timing_runs"), 0) << " runs) | " << format(row.queryP50, 1) << " / "
       << format(row.queryP99, 1) << " | " << format(row.broadP50, 1) << " + " << format(row.narrowP50, 1) << " | "
       << format(row.runValue("force_step_p99_N"), 3) << " / " << format(row.runValue("force_step_max_N"), 3) << " | "
       << format(row.runValue("proxy_inside_frames"), 0) << " | " << format(row.runValue("nan_frames"), 0) << " | "
       << format(row.runValue("removed"), 0) << " | " << (row.pareto ? "yes" : "") << " |\n";
  }
  if (report.pairs.size() > 1) {
    md << "\n## Every tool on every target it touched\n\n"
       << "The table above is of " << report.pairs.front().tool << " on " << report.pairs.front().target
       << ". Each tool and target that touched in the reference's run, at poses from their own frames in contact "
          "(each tool's renderer's frames); the closed loop of each is its renderer's whole run:\n\n"
       << "| # | setting | tool | target | pen. error p50 / p99 / max (mm) | normal error p50 / p99 (deg) | contact "
          "mismatches | dF p99 / unexplained p99 (N) | proxy inside | NaN |\n"
       << "|---:|---|---|---|---:|---:|---:|---:|---:|---:|\n";
    for (const StudyRow& row : report.rows)
      for (size_t p = 0; p < report.pairs.size() && p < row.pairs.size(); ++p) {
        const PairAccuracy& a = row.pairs[p];
        md << "| " << row.setting.index + 1 << " | " << row.setting.label() << " | " << report.pairs[p].tool << " | "
           << report.pairs[p].target << " | " << format(a.penetrationErrorP50, 3) << " / "
           << format(a.penetrationErrorP99, 3) << " / " << format(a.penetrationErrorMax, 3) << " | "
           << format(a.normalErrorP50, 2) << " / " << format(a.normalErrorP99, 2) << " | " << a.contactMismatches
           << " of " << a.comparedPoses << " | " << format(a.forceStepP99, 3) << " / "
           << format(a.unexplainedStepP99, 3) << " | " << format(a.proxyInsideFrames, 0) << " | "
           << format(a.nanFrames, 0) << " |\n";
      }
    md << "\nReferences:\n\n";
    for (const StudiedPair& pair : report.pairs)
      md << "- " << pair.tool << " on " << pair.target << ": " << pair.reference << "\n";
  }
  AtomicFile pairsFile(out / "pairs.csv");
  pairsFile.write(pairsCsv.str());
  pairsFile.commit();
  AtomicFile csvFile(out / "study.csv");
  csvFile.write(csv.str());
  csvFile.commit();
  AtomicFile mdFile(out / "study.md");
  mdFile.write(md.str());
  mdFile.commit();
  return {"study.csv", "pairs.csv", "study.md"};
}

}  // namespace trephine::study
