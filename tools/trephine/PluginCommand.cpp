#include "tools/trephine/PluginCommand.h"

#include <iostream>

#include "framework/core/PluginLoader.h"
#include "framework/core/Registry.h"
#include "framework/runtime/PluginCommands.h"
#include "tools/trephine/PlotScript.h"

namespace trephine::cli {

int runPluginCommand(const Arguments& arguments, const std::string& plugin) {
  PluginLoader loader;
  Registry registry;
  if (const auto error = loader.load(plugin, registry)) {
    std::cerr << "trephine " << arguments.command << ": " << *error << "\n";
    return kRuntimeFailure;
  }
  const PluginCommands* commands = registry.service<PluginCommands>();
  if (!commands) {
    std::cerr << "trephine " << arguments.command << ": the " << plugin << " plugin provides no commands\n";
    return kRuntimeFailure;
  }
  return commands->run(arguments, [](const PlotRequest& plot) {
    return runPlotScript(plot.script, plot.arguments, plot.drawn);
  });
}

}  // namespace trephine::cli
