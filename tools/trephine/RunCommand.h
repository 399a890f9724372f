#pragma once
#include <optional>
#include <string>

#include "framework/runtime/Simulation.h"
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

// The simulation options of the command line (--duration, --seed, --set,
// --realtime, --strict); nullopt with `error` set on a bad value.
std::optional<SimulationOptions> readSimulationOptions(const Arguments& arguments, std::string& error);

int runCommand(const Arguments& arguments);
int validateCommand(const Arguments& arguments);

}  // namespace trephine::cli
