#include "framework/runtime/RunOutputs.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>

#include "framework/core/AtomicFile.h"
#include "framework/core/Strings.h"
#include "framework/core/TextTable.h"
#include "framework/runtime/JsonWriter.h"
#include "framework/runtime/Simulation.h"

namespace trephine {

namespace {

void writeTiming(JsonWriter& json, const TimingHistogram& histogram) {
  const TimingSummary s = histogram.summary();
  json.beginObject();
  json.field("p50", s.p50).field("p90", s.p90).field("p99", s.p99).field("max", s.max).field("mean", s.mean);
  json.endObject();
}

std::string rateKey(double hz) { return formatDouble(hz); }

// Component path for an event's source pointer.
std::string sourcePath(const Simulation& simulation, const void* source) {
  for (const Component* c : simulation.scene().components())
    if (c == source) return c->path();
  return "";
}

// One tool's haptic figures, from its log (the value of `haptics`, and of
// each entry of `tools`).
void writeHapticFigures(JsonWriter& json, const HapticFrameLog& log, const Component* source) {
  const HapticStats s = log.stats();
  json.beginObject();
  json.field("source", source ? source->path() : std::string());
  json.field("frames", s.frames).field("contact_frames", s.contactFrames);
  json.key("force_N").beginObject().field("max", s.forceMax).field("mean", s.forceMean).endObject();
  json.key("force_step_N").beginObject().field("max", s.forceStepMax).field("p99", s.forceStepP99).endObject();
  json.key("penetration_mm").beginObject().field("max", s.penetrationMax).field("mean", s.penetrationMean).endObject();
  json.field("nan_frames", s.nanFrames).field("proxy_inside_frames", s.proxyInsideFrames);
  json.field("dropped_frames", s.droppedFrames);
  json.key("passivity").beginObject();
  json.field("energy_in_mJ", s.energyIn_mJ).field("min_energy_in_mJ", s.minEnergyIn_mJ);
  json.field("max_generated_mJ_per_100ms", s.maxGeneratedPer100ms_mJ);
  if (s.hasDeviceDamping) {
    json.field("device_damping_N_s_per_mm", s.deviceDamping);
    json.field("energy_in_with_device_mJ", s.energyInWithDevice_mJ);
    json.field("min_energy_in_with_device_mJ", s.minEnergyInWithDevice_mJ);
  }
  if (s.hasUnexplainedSteps) json.field("proxy_generated_mJ", s.proxyGenerated_mJ);
  json.endObject();
  if (s.hasUnexplainedSteps) {
    json.key("force_step_unexplained_N").beginObject();
    json.field("max", s.unexplainedStepMax).field("p99", s.unexplainedStepP99);
    json.endObject();
  }
  json.field("force_reversals", s.forceReversals);
  json.endObject();
}

// Every tool's line: "haptics   ..." and "passivity ...".
void printHapticFigures(std::ostream& out, const HapticStats& h) {
  out << std::setprecision(3) << h.frames << " frames, " << h.contactFrames << " in contact, |F| max " << h.forceMax
      << " N, step max " << h.forceStepMax << " N (p99 " << h.forceStepP99 << "), penetration max "
      << h.penetrationMax << " mm, NaN frames " << h.nanFrames << "\n";
  out << "passivity energy in " << h.energyIn_mJ << " mJ, min " << h.minEnergyIn_mJ << " mJ, generated max "
      << h.maxGeneratedPer100ms_mJ << " mJ per 100 ms (elastic energy given back at release counts), "
      << h.forceReversals << " force reversals";
  if (h.hasUnexplainedSteps)
    out << ", unexplained step max " << h.unexplainedStepMax << " N (p99 " << h.unexplainedStepP99
        << "), proxy generated " << h.proxyGenerated_mJ << " mJ";
  if (h.hasDeviceDamping)
    out << "\n          with the device's damping " << std::defaultfloat << h.deviceDamping << std::fixed
        << " N s/mm: energy in " << h.energyInWithDevice_mJ << " mJ, min " << h.minEnergyInWithDevice_mJ << " mJ";
  out << "\n";
}

// Figures by dotted path as nested objects: "a.b" and "a.c" in one "a".
// Figures of one prefix are written together, in their first one's place.
void writeNestedFigures(JsonWriter& json, const std::vector<Counter>& figures, const std::string& prefix) {
  std::vector<std::string> written;
  for (const Counter& figure : figures) {
    if (figure.name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = figure.name.substr(prefix.size());
    const size_t dot = rest.find('.');
    const std::string key = rest.substr(0, dot);
    if (std::find(written.begin(), written.end(), key) != written.end()) continue;
    written.push_back(key);
    if (dot == std::string::npos) {
      json.field(key, figure.value);
    } else {
      json.key(key).beginObject();
      writeNestedFigures(json, figures, prefix + key + ".");
      json.endObject();
    }
  }
}

// The tools whose frames touched `target`: path length of the displayed
// tool (the proxy) over the whole run, time in contact with the target, and
// the force while in contact with it (max, mean).
void writeToolsOn(JsonWriter& json, const Simulation& simulation, const void* target) {
  json.key("tools").beginObject();
  for (const Simulation::ToolLog& tool : simulation.toolLogs()) {
    const HapticFrameLog& log = *tool.log;
    double path = 0, contact = 0, forceMax = 0, forceSum = 0;
    size_t contactFrames = 0;
    bool touched = false;
    for (size_t i = 0; i < log.size(); ++i) {
      const HapticFrame& f = log[i];
      if (i > 0 && f.proxy.allFinite() && log[i - 1].proxy.allFinite()) path += (f.proxy - log[i - 1].proxy).norm();
      if (f.target != target || f.contacts <= 0) continue;
      touched = true;
      ++contactFrames;
      if (i + 1 < log.size()) contact += log[i + 1].t - f.t;
      const double force = f.force.allFinite() ? f.force.norm() : 0.0;
      forceMax = std::max(forceMax, force);
      forceSum += force;
    }
    if (!touched) continue;
    json.key(tool.renderer->path()).beginObject();
    json.field("path_length_mm", path).field("contact_s", contact);
    json.key("force_N").beginObject().field("max", forceMax);
    json.field("mean", contactFrames ? forceSum / double(contactFrames) : 0.0).endObject();
    json.endObject();
  }
  json.endObject();
}

}  // namespace

void writeSummaryJson(const Simulation& simulation, const FinishContext* finish, std::ostream& out) {
  JsonWriter json(out);
  const Scheduler& scheduler = simulation.scheduler();
  json.beginObject();
  json.field("scene", simulation.scene().file().string());
  json.field("seed", static_cast<unsigned long long>(simulation.plan().seed));
  json.field("mode", simulation.plan().realtime ? "realtime" : "virtual");
  json.field("duration_s", simulation.plan().duration);
  json.field("sim_time_s", scheduler.simulatedTime());
  json.field("wall_time_s", simulation.wallTime());
  json.field("complete", simulation.complete());
  if (!simulation.complete()) json.field("reason", simulation.incompleteReason());
  json.key("plugins").beginArray();
  for (const std::string& p : simulation.scene().plugins()) json.value(p);
  json.endArray();

  // Per component: timing from the scheduler, counters from the component.
  std::map<const Component*, const GroupMember*> timing;
  for (const RateGroup& g : scheduler.groups())
    for (const GroupMember& m : g.members) timing[m.component] = &m;
  std::map<std::string, double> totals;  // counters summed over components, for the drilling key
  json.key("components").beginObject();
  for (const Component* c : simulation.scene().components()) {
    json.key(c->path()).beginObject();
    json.field("type", c->typeName());
    std::vector<Fact> facts;
    c->reportFacts(facts);
    for (const Fact& fact : facts) json.field(fact.name, fact.value);
    json.field("rate_hz", c->rateHz());
    const auto it = timing.find(c);
    json.field("calls", it == timing.end() ? 0ull : static_cast<unsigned long long>(it->second->calls));
    json.key("time_us");
    writeTiming(json, it == timing.end() ? TimingHistogram() : it->second->histogram);
    json.field("deadline_misses", it == timing.end() ? 0ull : static_cast<unsigned long long>(it->second->overruns));
    std::vector<Counter> counters;
    c->reportCounters(counters);
    if (!counters.empty()) {
      json.key("counters").beginObject();
      for (const Counter& counter : counters) {
        json.field(counter.name, counter.value);
        totals[counter.name] += counter.value;
      }
      json.endObject();
    }
    json.endObject();
  }
  json.endObject();

  json.key("groups").beginObject();
  for (const RateGroup& g : scheduler.groups()) {
    // "1000", or "1000:fem" for a named group at that rate.
    json.key(rateKey(g.rateHz) + (g.name.empty() ? "" : ":" + g.name)).beginObject();
    if (!g.name.empty()) json.field("group", g.name);
    json.field("calls", static_cast<unsigned long long>(g.calls));
    json.key("time_us");
    writeTiming(json, g.stepHistogram);
    json.field("deadline_misses", static_cast<unsigned long long>(g.deadlineMisses));
    json.key("components").beginArray();
    for (const GroupMember& m : g.members) json.value(m.component->path());
    json.endArray();
    if (simulation.plan().realtime) {
      json.field("calls_per_s", g.callsPerSecond());
      json.key("wake_lateness_us");
      writeTiming(json, g.wakeLateness);
      json.field("skipped_ticks", static_cast<unsigned long long>(g.skippedTicks));
      json.field("realtime_priority", g.realtimePriority);
      if (g.pacer) {
        // Frames started by the device's input, and by the clock's bound with none come.
        json.field("paced_frames", static_cast<unsigned long long>(g.pacedFrames));
        json.field("unpaced_frames", static_cast<unsigned long long>(g.unpacedFrames));
      }
    }
    json.endObject();
  }
  json.endObject();

  json.key("haptics");
  writeHapticFigures(json, simulation.hapticLog(), simulation.hapticLogOwner());
  // Every tool, by its force renderer's path (trace.csv's too).
  json.key("tools").beginObject();
  for (const Simulation::ToolLog& tool : simulation.toolLogs()) {
    json.key(tool.renderer->path());
    writeHapticFigures(json, *tool.log, tool.renderer);
  }
  json.endObject();
  json.key("drilling").beginObject().field("voxels_removed", totals["voxels_removed"]).endObject();
  for (const Component* c : simulation.scene().components()) {
    const std::optional<SummaryBlock> block = c->summaryBlock();
    if (!block) continue;
    json.key(block->name).beginObject();
    json.field("source", c->path());
    writeNestedFigures(json, block->figures, "");
    if (block->toolsOn) writeToolsOn(json, simulation, block->toolsOn);
    json.endObject();
  }

  const EventLog& events = simulation.events();
  json.key("events").beginArray();
  for (size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    json.beginObject().field("t", e.t).field("kind", e.kind);
    if (*e.detail) json.field("detail", e.detail);
    json.field("component", sourcePath(simulation, e.source));
    if (e.value != 0) json.field("value", e.value);
    if (e.hasPosition()) {
      json.key("position").beginArray();
      for (double x : e.position) json.value(x);
      json.endArray();
    }
    json.endObject();
  }
  json.endArray();
  json.field("events_dropped", static_cast<unsigned long long>(events.dropped()));

  if (finish) {
    json.key("outputs").beginArray();
    for (const auto& o : finish->outputs())
      json.beginObject().field("component", o.component).field("file", o.file).endObject();
    json.endArray();
    if (!finish->errors().empty()) {
      json.key("output_errors").beginArray();
      for (const auto& e : finish->errors()) json.value(e);
      json.endArray();
    }
  }
  json.endObject();
}

void writeTraceCsv(const Simulation& simulation, std::ostream& out) { writeTraceCsv(simulation.hapticLog(), out); }

void writeTraceCsv(const HapticFrameLog& log, std::ostream& out) {
  out << kTraceHeader << "\n";
  std::string row;
  for (size_t i = 0; i < log.size(); ++i) {
    const HapticFrame& f = log[i];
    row.clear();
    row += formatDouble(f.t);
    for (const Vec3* v : {&f.device, &f.proxy, &f.force}) {
      for (int k = 0; k < 3; ++k) row += "," + formatDouble((*v)[k]);
    }
    row += "," + formatDouble(f.penetration);
    for (int k = 0; k < 3; ++k) row += "," + formatDouble(f.normal[k]);
    row += "," + std::to_string(f.contacts) + "," + formatDouble(f.rawPenetration) + "," +
           std::to_string(f.primitives) + "," + (f.proxyInside ? "1" : "0") + "," + std::to_string(f.removed) + "\n";
    out << row;
  }
}

void writeTimingsCsv(const Simulation& simulation, std::ostream& out) {
  out << "component,rate_hz,call,t,duration_us\n";
  for (const RateGroup& g : simulation.scheduler().groups()) {
    for (const GroupMember& m : g.members) {
      const std::string prefix = m.component->path() + "," + formatDouble(g.rateHz) + ",";
      for (uint64_t k = 0; k < m.callUs.size(); ++k) {
        if (std::isnan(m.callUs[k])) continue;  // not called: skipped in real time, or after a stop
        out << prefix << k << "," << formatDouble(static_cast<double>(k) / g.rateHz) << ","
            << formatDouble(static_cast<double>(m.callUs[k])) << "\n";
      }
    }
  }
}

std::vector<std::string> writeRunOutputs(const Simulation& simulation, FinishContext& finish,
                                         const std::filesystem::path& directory) {
  // Each file whole or not at all (a full disk leaves no file cut mid-row).
  // summary.json comes last so that it lists the files that failed; the
  // space a failed file took is free again by then.
  std::vector<std::string> written;
  const auto write = [&](const char* name, const std::function<void(std::ostream&)>& writer) {
    try {
      writeFileAtomically(directory / name, writer);
      written.emplace_back(name);
    } catch (const FileWriteError& e) {
      finish.runError(e.what());
    }
  };
  write("trace.csv", [&](std::ostream& o) { writeTraceCsv(simulation, o); });
  for (const Simulation::ToolLog& tool : simulation.toolLogs())
    if (!tool.writesTrace) {
      const std::string name = toolTraceName(*tool.renderer);
      write(name.c_str(), [&](std::ostream& o) { writeTraceCsv(*tool.log, o); });
    }
  write("timings.csv", [&](std::ostream& o) { writeTimingsCsv(simulation, o); });
  write("summary.json", [&](std::ostream& o) { writeSummaryJson(simulation, &finish, o); });
  return written;
}

void printRunSummary(const Simulation& simulation, std::ostream& out) {
  const Scheduler& scheduler = simulation.scheduler();
  out << "scene     " << simulation.scene().file().string() << "\n";
  out << "mode      " << (simulation.plan().realtime ? "realtime" : "virtual") << ", seed " << simulation.plan().seed
      << ", simulated " << formatDouble(scheduler.simulatedTime()) << " s in " << std::fixed << std::setprecision(3)
      << simulation.wallTime() << " s wall\n";
  if (!simulation.complete()) out << "status    INCOMPLETE: " << simulation.incompleteReason() << "\n";
  // Fixed decimals, each column as wide as its widest value.
  const auto fixed = [](double value, int decimals) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(decimals) << value;
    return text.str();
  };
  std::vector<std::vector<std::string>> groups{{"rate_hz", "calls", "p50_us", "p99_us", "max_us", "misses", "group"}};
  for (const RateGroup& g : scheduler.groups()) {
    const TimingSummary s = g.stepHistogram.summary();
    groups.push_back({formatDouble(g.rateHz), std::to_string(g.calls), fixed(s.p50, 2), fixed(s.p99, 2),
                      fixed(s.max, 2), std::to_string(g.deadlineMisses), g.name.empty() ? "-" : g.name});
  }
  const std::string groupTable = formatColumns(groups, "          ");
  out << "groups" << groupTable.substr(6);
  if (simulation.plan().realtime) {
    std::vector<std::vector<std::string>> late{
        {"rate_hz", "calls/s", "wake_late_p50_us", "p99_us", "max_us", "skipped", "SCHED_FIFO", "group"}};
    for (const RateGroup& g : scheduler.groups()) {
      const TimingSummary s = g.wakeLateness.summary();
      late.push_back({formatDouble(g.rateHz), fixed(g.callsPerSecond(), 1), fixed(s.p50, 3), fixed(s.p99, 3),
                      fixed(s.max, 3), std::to_string(g.skippedTicks), g.realtimePriority ? "yes" : "no",
                      g.name.empty() ? "-" : g.name});
    }
    const std::string lateTable = formatColumns(late, "          ");
    out << "realtime" << lateTable.substr(8);
  }
  // One haptics line (and its passivity line) per tool; with several, each named by its renderer.
  const std::vector<Simulation::ToolLog> tools = simulation.toolLogs();
  for (const Simulation::ToolLog& tool : tools) {
    if (tools.size() > 1) out << "tool      " << tool.renderer->path() << (tool.writesTrace ? " (trace.csv)" : " (" + toolTraceName(*tool.renderer) + ")") << "\n";
    out << "haptics   ";
    printHapticFigures(out, tool.log->stats());
  }
  // What the user should know of: each event of a kind that says something
  // went other than planned, up to a few, and a count of every kind.
  const EventLog& events = simulation.events();
  std::map<std::string, size_t> kinds;
  size_t told = 0;
  for (size_t i = 0; i < events.size(); ++i) {
    const Event& e = events[i];
    ++kinds[e.kind];
    const std::string_view kind = e.kind;
    // A device that takes none of the forces sent, or a bridge lost under the run.
    const bool deviceUnheard = (kind == "bridge_forces_unheard" && std::string_view(e.detail) != "recovered") ||
                               kind == "bridge_lost";
    if ((kind == "tool_starts_inside" || kind == "haptic_released" || kind == "fem_diverged" ||
         kind == "tick_failed" || deviceUnheard) &&
        told++ < 5)
      out << "warning   " << std::setprecision(3) << e.t << " s, " << sourcePath(simulation, e.source) << ": "
          << e.kind << (*e.detail ? std::string(": ") + e.detail : std::string()) << "\n";
  }
  if (!kinds.empty()) {
    out << "events    " << events.size() + events.dropped() << " (";
    bool first = true;
    for (const auto& [kind, count] : kinds) {
      out << (first ? "" : ", ") << kind << " " << count;
      first = false;
    }
    out << (events.dropped() ? ", " + std::to_string(events.dropped()) + " not kept" : std::string()) << ")\n";
  }
  out.unsetf(std::ios::fixed);
}

}  // namespace trephine
