#pragma once
#include "tools/trephine/CommandLine.h"

namespace trephine::cli {

// trephine cellsize MESH --tool RADIUS: the cell size of TetraBrain's grid for
// a spherical tool's pointshell (the tool query's cost model), and with
// --experiment the measured optimum.
int toolCellSizeCommand(const Arguments& arguments);

}  // namespace trephine::cli
