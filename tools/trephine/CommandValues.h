#pragma once
// Values the subcommands read from their options and arguments.
#include <optional>
#include <string>

#include "framework/data/TetMesh.h"
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

// The number option `name` (or `fallback` when absent); on a bad value,
// nullopt and `error` names the option and the text.
std::optional<double> numberOption(const Arguments& a, const std::string& name, double fallback, std::string& error);

// A tetrahedral mesh file (.mesh, .vtu, .vtk, .msh, .node/.ele) or phantom:SPEC. Throws with the reason.
TetMesh loadTetMesh(const std::string& name);

}  // namespace trephine::cli
