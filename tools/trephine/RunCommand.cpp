#include "tools/trephine/RunCommand.h"

#include <charconv>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <optional>

#include <unistd.h>

#include "framework/core/Strings.h"
#include "framework/runtime/RunOutputs.h"
#include "framework/runtime/RunProgress.h"
#include "framework/runtime/Simulation.h"

namespace trephine::cli {

namespace {

std::atomic<bool> g_stopRequested{false};
std::atomic<int> g_signal{0};

extern "C" void onSignal(int signal) {
  g_signal = signal;
  g_stopRequested = true;
}

}  // namespace

std::optional<SimulationOptions> readSimulationOptions(const Arguments& a, std::string& error) {
  SimulationOptions options;
  options.overrides = a.overrides;
  options.realtime = a.has("--realtime");
  options.strict = a.has("--strict");
  if (auto d = a.get("--duration")) {
    double seconds = 0;
    if (FieldTraits<double>::parse(*d, seconds) || !(seconds > 0)) {
      error = "--duration expects a positive number of seconds, got '" + *d + "'";
      return std::nullopt;
    }
    options.duration = seconds;
  }
  if (auto s = a.get("--seed")) {
    uint64_t seed = 0;
    const auto result = std::from_chars(s->data(), s->data() + s->size(), seed);
    if (s->empty() || result.ec != std::errc() || result.ptr != s->data() + s->size()) {
      error = "--seed expects a non-negative integer, got '" + *s + "'";
      return std::nullopt;
    }
    options.seed = seed;
  }
  return options;
}

int validateCommand(const Arguments& a) {
  if (a.positional.size() != 1) {
    std::cerr << "usage: trephine validate SCENE [--duration S] [--seed N] [--set path.field=value ...] [--strict]\n";
    return kUsage;
  }
  std::string error;
  const auto options = readSimulationOptions(a, error);
  if (!options) {
    std::cerr << "trephine: " << error << "\n";
    return kUsage;
  }
  Diagnostics diagnostics;
  auto simulation = Simulation::fromFile(a.positional[0], *options, diagnostics);
  if (!simulation) {
    diagnostics.print(std::cerr);
    return kSceneError;
  }
  diagnostics.print(std::cerr);  // warnings, if any
  std::cout << "ok\n";
  return kOk;
}

int runCommand(const Arguments& a) {
  if (a.positional.size() != 1) {
    std::cerr << "usage: trephine run SCENE [--duration S] [--out DIR] [--realtime [--view [PORT]]] [--seed N] "
                 "[--set path.field=value ...] [--strict]\n";
    return kUsage;
  }
  std::string error;
  auto options = readSimulationOptions(a, error);
  if (!options) {
    std::cerr << "trephine: " << error << "\n";
    return kUsage;
  }
  const std::filesystem::path scene = a.positional[0];
  const std::filesystem::path out = a.get("--out").value_or("runs/" + scene.stem().string());
  options->outputDirectory = out;
  if (auto port = a.get("--view")) {
    int value = -1;
    const auto result = std::from_chars(port->data(), port->data() + port->size(), value);
    if (port->empty() || result.ec != std::errc() || result.ptr != port->data() + port->size() || value < 0 ||
        value > 65535) {
      std::cerr << "trephine: --view takes a port (0 to 65535; 0: any free one), not '" << *port << "'\n";
      return kUsage;
    }
    if (!options->realtime) {
      std::cerr << "trephine: --view needs --realtime (in virtual time the run is over before a browser connects)\n";
      return kUsage;
    }
    options->liveViewPort = value;
  }

  Diagnostics diagnostics;
  auto simulation = Simulation::fromFile(scene, *options, diagnostics);
  if (!simulation) {
    diagnostics.print(std::cerr);
    return kSceneError;
  }
  diagnostics.print(std::cerr);
  if (options->liveViewPort >= 0) {
    bool exporter = false;
    for (const Component* c : simulation->scene().components()) exporter = exporter || c->typeName() == "VtkExporter";
    if (!exporter) {
      std::cerr << "trephine: --view streams what the scene's VtkExporter names (the skull, the brain, the tool): "
                << scene.string() << " has none; add one (see scenes/integrated.xml)\n";
      return kSceneError;
    }
  }

  // A reader of stderr or stdout that goes away (`trephine run ... 2>&1 | head`)
  // must not end the run: the progress lines and the summary are then lost,
  // the run's files are not.
  std::signal(SIGPIPE, SIG_IGN);
  // Ctrl-C stops the run between steps; everything measured so far is written.
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  {
    // A line every 5 s on stderr (rewritten each second on a terminal) while it runs.
    const bool terminal = isatty(STDERR_FILENO) != 0;
    std::optional<RunProgress> progress;
    if (!a.has("--quiet"))
      progress.emplace(simulation->scheduler(), simulation->plan().duration, std::cerr, terminal ? 1.0 : 5.0, terminal);
    simulation->run(g_stopRequested);
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (g_signal != 0 && !simulation->complete())
    simulation->markInterrupted(std::string("interrupted by ") + (g_signal == SIGINT ? "SIGINT" : "SIGTERM"));

  std::vector<std::string> outputErrors;
  std::vector<std::string> written;
  try {
    written = simulation->writeOutputs(out, &outputErrors);
  } catch (const std::exception& e) {
    std::cerr << "trephine: cannot write outputs to " << out.string() << ": " << e.what() << "\n";
    return kRuntimeFailure;
  }
  if (!a.has("--quiet")) {
    printRunSummary(*simulation, std::cout);
    std::cout << "outputs   " << out.string() << "/ (";
    for (size_t i = 0; i < written.size(); ++i) std::cout << (i ? ", " : "") << written[i];
    std::cout << ")\n";
  }
  for (const std::string& e : outputErrors) std::cerr << "trephine: " << e << "\n";
  if (!simulation->complete()) {
    std::cerr << "trephine: run incomplete: " << simulation->incompleteReason() << "\n";
    return kRuntimeFailure;
  }
  return outputErrors.empty() ? kOk : kRuntimeFailure;
}

}  // namespace trephine::cli
