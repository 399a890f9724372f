#pragma once
// Subcommands a plugin runs (framework/runtime/PluginCommands.h): the program
// loads the plugin and hands it the parsed command line, and draws the plots
// it asks for.
#include <string>

#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

// Runs `arguments.command` in `plugin`'s PluginCommands; a plugin that cannot
// be loaded, or provides no commands, is a runtime failure (exit code 3).
int runPluginCommand(const Arguments& arguments, const std::string& plugin);

// `trephine cellsize`: the brain plugin's grid cell-size experiments.
inline int cellSizeCommand(const Arguments& arguments) { return runPluginCommand(arguments, "tetra_brain"); }

}  // namespace trephine::cli
